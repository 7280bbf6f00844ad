// Levelled diagnostics: levels and their names, attribution to a file (only where none is
// named), and the plain message list the CLI shows.
#include "core/diagnostic.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace lidarscout {
namespace {

TEST(Diagnostic, LevelsHaveTheirNames) {
    EXPECT_STREQ(level_name(DiagnosticLevel::note), "note");
    EXPECT_STREQ(level_name(DiagnosticLevel::warning), "warning");
}

TEST(Diagnostic, ListKeepsOrderLevelAndOffset) {
    Diagnostics d;
    EXPECT_TRUE(d.empty());
    d.warn("bad key", 500);
    d.note("read anyway");
    d.add({DiagnosticLevel::warning, "b.laz", 7, "short"});
    ASSERT_EQ(d.size(), 3u);
    EXPECT_EQ(d[0], (Diagnostic{DiagnosticLevel::warning, "", 500, "bad key"}));
    EXPECT_EQ(d[1], (Diagnostic{DiagnosticLevel::note, "", std::nullopt, "read anyway"}));
    EXPECT_EQ(d.messages(), (std::vector<std::string>{"bad key", "read anyway", "short"}));
}

TEST(Diagnostic, AttributionFillsOnlyMissingFiles) {
    Diagnostics d;
    d.warn("one");
    d.add({DiagnosticLevel::warning, "b.laz", std::nullopt, "two"});
    d.attribute_to("a.laz");
    EXPECT_EQ(d[0].file, "a.laz");
    EXPECT_EQ(d[1].file, "b.laz");
    Diagnostics all;
    all.append(d);
    all.append(d);
    EXPECT_EQ(all.size(), 4u);
    all.clear();
    EXPECT_TRUE(all.empty());
}

}  // namespace
}  // namespace lidarscout
