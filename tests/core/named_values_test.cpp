// Named enumeration values: names parse to their values, an unknown name is an Error that
// lists the known ones, and every value has its name back.
#include "core/named_values.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <string_view>

namespace lidarscout {
namespace {

enum class Fruit { apple, pear };
constexpr std::array<std::string_view, 2> kFruitNames = {"apple", "pear"};

TEST(NamedValues, NamesParseToValuesAndBack) {
    EXPECT_EQ(parse_named<Fruit>(kFruitNames, "pear", "fruit"), Fruit::pear);
    EXPECT_EQ(name_of(kFruitNames, Fruit::apple), "apple");
    EXPECT_EQ(name_of(kFruitNames, parse_named<Fruit>(kFruitNames, "apple", "fruit")), "apple");
}

TEST(NamedValues, UnknownNameListsTheKnownOnes) {
    try {
        parse_named<Fruit>(kFruitNames, "plum", "fruit");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "unknown fruit 'plum' (known: apple, pear)");
    }
}

TEST(NamedValues, ValueOutsideTheTableIsAnError) {
    EXPECT_THROW(name_of(kFruitNames, static_cast<Fruit>(5)), Error);
}

}  // namespace
}  // namespace lidarscout
