// ProcessBudget: the program's share taken off the process's budget before the scheduler gets the
// rest; the network only where it fits; below what the viewer needs, one line with the figure and
// the least data; the most seen outside the ledger counts; an overview that fills the data's share said; the
// network left out where a country's overview would fill what it leaves, its share then given to data.
#include <gtest/gtest.h>

#include "viewer/process_budget.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::uint64_t MiB = 1ull << 20;

TEST(ProcessBudget, TheProgramsShareIsTakenOffTheBudget) {
    const ProcessBudget b(1024 * MiB, 150 * MiB, true);
    const ProcessBudgetPlan p = b.plan();
    EXPECT_TRUE(p.network);
    EXPECT_EQ(p.data, 1024 * MiB - 150 * MiB - kNetworkBytes);
    EXPECT_EQ(p.note, "");
}

TEST(ProcessBudget, TheMostSeenOutsideTheLedgerCounts) {
    ProcessBudget b(1024 * MiB, 150 * MiB, false);
    b.observe(500 * MiB, 100 * MiB);  // 400 MiB outside
    b.observe(450 * MiB, 200 * MiB);  // 250: less, the 400 stays
    EXPECT_EQ(b.outside(), 400 * MiB);
    EXPECT_EQ(b.plan().data, 624 * MiB);
    b.observe(50 * MiB, 100 * MiB);  // a ledger over the resident size: nothing outside
    EXPECT_EQ(b.outside(), 400 * MiB);
}

TEST(ProcessBudget, WhatTheOpeningHeldIsForgottenOnceItIsOver) {
    ProcessBudget b(1024 * MiB, 150 * MiB, false);
    b.observe(700 * MiB, 50 * MiB);  // a catalog's blocks and a sidecar's buffers: 650 MiB outside
    EXPECT_EQ(b.plan().data, 374 * MiB);
    b.opening_over();
    EXPECT_EQ(b.outside(), 150 * MiB);  // what it held at start, until seen again
    b.observe(800 * MiB, 400 * MiB);
    EXPECT_EQ(b.outside(), 400 * MiB);
    EXPECT_EQ(b.plan().data, 624 * MiB);
    b.observe(900 * MiB, 550 * MiB);  // less outside: the most seen since stays
    EXPECT_EQ(b.outside(), 400 * MiB);
}

TEST(ProcessBudget, TheNetworkOnlyWhereItFits) {
    const ProcessBudgetPlan p = ProcessBudget(256 * MiB, 150 * MiB, true).plan();
    EXPECT_FALSE(p.network);
    EXPECT_EQ(p.data, 106 * MiB);
    EXPECT_EQ(p.note, "the memory budget at start (256 MiB) left no room for the heightmap network (150 MiB with its "
                      "libraries): linear heightmaps only");
    EXPECT_FALSE(p.below);
    EXPECT_FALSE(ProcessBudget(4096 * MiB, 150 * MiB, false).plan().network);  // not wanted: no note
    EXPECT_EQ(ProcessBudget(4096 * MiB, 150 * MiB, false).plan().note, "");
}

TEST(ProcessBudget, BelowWhatTheViewerNeedsItSaysSoAndRunsWithTheLeast) {
    ProcessBudget b(128 * MiB, 150 * MiB, true);
    const ProcessBudgetPlan p = b.plan();
    EXPECT_FALSE(p.network);
    EXPECT_EQ(p.data, kLeastDataBytes);
    EXPECT_EQ(p.note, "memory budget 128 MiB is below the 182 MiB the viewer needs to run (150 MiB for the program, "
                      "its libraries, window and threads, 32 MiB for data): running with 182 MiB, linear heightmaps "
                      "only");
    EXPECT_TRUE(p.below);
    b.set_asked(512 * MiB);  // a larger budget from the panel: room again (the network stays off)
    EXPECT_EQ(b.plan().data, 362 * MiB);
    EXPECT_EQ(b.plan().note, "the memory budget at start (128 MiB) left no room for the heightmap network (150 MiB "
                             "with its libraries): linear heightmaps only");
    EXPECT_FALSE(b.plan().below);
}

TEST(ProcessBudget, AnOverviewThatFillsTheDataShareIsSaid) {
    EXPECT_EQ(overview_fills_note(300 * MiB, 422 * MiB, 152100), "");
    EXPECT_EQ(overview_fills_note(423 * MiB, 422 * MiB, 152100),
              "the overview of 152100 tiles (chunk points, patches, nearest heightmaps) holds 423 MiB of the 422 MiB "
              "left for data: little or no room for full-resolution points (a larger --memory gives it)");
    EXPECT_NE(overview_fills_note(380 * MiB, 422 * MiB, 9), "");  // 90%
}

TEST(ProcessBudget, TheNetworkIsLeftOutWhereTheOverviewWouldFillWhatItLeaves) {
    ProcessBudget b(1024 * MiB, 150 * MiB, true);
    b.observe(700 * MiB, 100 * MiB);  // a country's metadata: 600 MiB outside the ledger
    // With the network: 1024 - 600 - 150 = 274 MiB for data.
    EXPECT_TRUE(b.network_leaves_room(200 * MiB));
    EXPECT_FALSE(b.network_leaves_room(330 * MiB));  // the 152,100-tile replica's chunk points and patches
    EXPECT_FALSE(ProcessBudget(700 * MiB, 600 * MiB, true).network_leaves_room(0));  // no room at all
    EXPECT_EQ(b.plan().data, 424 * MiB);
    b.network_declined();  // its share is the data's now, and the scheduler's note says why (none here)
    EXPECT_FALSE(b.plan().network);
    EXPECT_EQ(b.plan().note, "");
    ProcessBudget small(1024 * MiB, 150 * MiB, true);  // nothing seen beyond the start: the reservation counted
    EXPECT_EQ(small.plan().data, 1024 * MiB - 150 * MiB - kNetworkBytes);
    small.network_declined();
    EXPECT_EQ(small.plan().data, 1024 * MiB - 150 * MiB);
}

}  // namespace
}  // namespace lidarscout::viewer
