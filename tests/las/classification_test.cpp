// ASPRS class names: the standard classes, the reserved and the user-defined ranges.
#include <gtest/gtest.h>

#include "las/classification.hpp"

namespace lidarscout::las {
namespace {

TEST(LasClassification, StandardClassesHaveTheirNames) {
    EXPECT_EQ(class_name(2), "ground");
    EXPECT_EQ(class_name(5), "high vegetation");
    EXPECT_EQ(class_name(6), "building");
    EXPECT_EQ(class_name(9), "water");
    EXPECT_EQ(class_name(18), "high noise");
    EXPECT_EQ(class_name(19), "overhead structure");  // R14/R15's additions
    EXPECT_EQ(class_name(22), "temporal exclusion");
}

TEST(LasClassification, ReservedAndUserDefinedRanges) {
    EXPECT_EQ(class_name(23), "reserved (23)");
    EXPECT_EQ(class_name(63), "reserved (63)");
    EXPECT_EQ(class_name(64), "user defined (64)");
    EXPECT_EQ(class_name(255), "user defined (255)");
}

}  // namespace
}  // namespace lidarscout::las
