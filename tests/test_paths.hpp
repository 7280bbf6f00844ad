// Where the tests find the repository, the build tree, ../shared/data and the CLI. The values live in one
// generated file (test_paths.cpp in the build tree), not in every test's compile line, so that a test's
// object does not depend on where the checkout lies (a second worktree's build reuses the compiler cache).
#pragma once

namespace lidarscout::test::paths {
extern const char* const data_dir;    // ../shared/data
extern const char* const source_dir;  // the repository's root
extern const char* const build_dir;   // the build tree
extern const char* const cli;         // the lidarscout program
}  // namespace lidarscout::test::paths

// (a benchmark that borrows a test fixture may define them on its compile line instead)
#ifndef LIDARSCOUT_DATA_DIR
#define LIDARSCOUT_DATA_DIR (::lidarscout::test::paths::data_dir)
#endif
#ifndef LIDARSCOUT_SOURCE_DIR
#define LIDARSCOUT_SOURCE_DIR (::lidarscout::test::paths::source_dir)
#endif
#ifndef LIDARSCOUT_BUILD_DIR
#define LIDARSCOUT_BUILD_DIR (::lidarscout::test::paths::build_dir)
#endif
#ifndef LIDARSCOUT_CLI
#define LIDARSCOUT_CLI (::lidarscout::test::paths::cli)
#endif
