// core/cell_table: values found by cell as a map finds them, in the order added, a reference to one
// good however many cells come after it, and the bytes held as stated.
#include "core/cell_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace lidarscout {
namespace {

TEST(CellTable, FindsWhatAMapFinds) {
    CellTable<std::string> table;
    std::map<CellKey, std::string> map;
    Rng rng(7);
    for (int i = 0; i < 50'000; ++i) {
        // Keys of a few hundred cells a side, negative ones too, many added again.
        const CellKey key{static_cast<std::int32_t>(rng.next() % 300) - 150,
                          static_cast<std::int32_t>(rng.next() % 300) - 150};
        const auto [value, added] = table.try_emplace(key);
        EXPECT_EQ(added, !map.count(key));
        *value += "x";
        map[key] += "x";
    }
    ASSERT_EQ(table.size(), map.size());
    for (const auto& [key, value] : map) {
        ASSERT_NE(table.find(key), nullptr);
        EXPECT_EQ(*table.find(key), value);
        EXPECT_EQ(table.at(key), value);
    }
    EXPECT_EQ(table.find({1000, 1000}), nullptr);
    EXPECT_THROW(table.at({1000, 1000}), std::out_of_range);
    EXPECT_EQ(CellTable<int>().find({0, 0}), nullptr) << "an empty table";
}

TEST(CellTable, KeepsTheOrderAddedAndItsReferences) {
    CellTable<std::vector<int>> table;
    std::vector<std::vector<int>*> first;
    for (int i = 0; i < 5000; ++i) {
        std::vector<int>& v = table[{i % 97, i / 97}];
        v.push_back(i);
        if (i < 100) first.push_back(&v);
    }
    for (int i = 0; i < 100; ++i) {
        const CellKey key{i % 97, i / 97};
        EXPECT_EQ(first[i], &table[key]) << "never moved as cells came";
    }
    for (std::size_t i = 0; i < table.size(); ++i) {
        EXPECT_EQ(table.key(i), (CellKey{static_cast<int>(i % 97), static_cast<int>(i / 97)}));
        EXPECT_EQ(table.value(i), std::vector<int>{static_cast<int>(i)});
    }
}

TEST(CellTable, HoldsTheBytesItStates) {
    CellTable<std::uint64_t> table;
    EXPECT_EQ(table.memory_bytes(), 0u) << "nothing before the first cell";
    table.reserve(100'000);
    const std::size_t reserved = table.memory_bytes();
    for (int i = 0; i < 100'000; ++i) table[{i, -i}] = static_cast<std::uint64_t>(i);
    EXPECT_LE(table.memory_bytes(), reserved + 100'000 * sizeof(std::uint64_t) + 1024 * 8 + 4096)
        << "reserved: only the values' chunks grow";
    const std::size_t per_cell = table.memory_bytes() / table.size();
    EXPECT_LE(per_cell, sizeof(std::uint64_t) + 2 * CellTable<std::uint64_t>::kBytesPerCell);
    CellTable<std::uint64_t> small;
    small[{1, 2}] = 3;
    EXPECT_LT(small.memory_bytes(), 1024u) << "a small table stays small";
}

TEST(CellTable, CellsSortAsTheirOrderHasThem) {
    Rng rng(3);
    std::vector<CellKey> cells;
    for (int i = 0; i < 20'000; ++i) {
        const auto v = [&] { return static_cast<std::int32_t>(rng.next()) >> (rng.next() % 31); };  // near 0 and far
        cells.push_back({v(), v()});
    }
    cells.push_back({std::numeric_limits<std::int32_t>::min(), 0});
    cells.push_back({std::numeric_limits<std::int32_t>::max(), -1});
    std::vector<CellKey> expected = cells;
    std::sort(expected.begin(), expected.end());
    sort_cells(cells);
    EXPECT_EQ(cells, expected);
}

}  // namespace
}  // namespace lidarscout
