// The whole formats/ corpus: every file is either read or rejected with a clear error naming
// the file, exactly as its row in INDEX.md says.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

struct IndexRow {
    std::string file;
    bool decodes;
};

std::vector<IndexRow> index_rows() {
    std::vector<IndexRow> rows;
    for (const auto& [name, ok] : test::index_outcomes()) rows.push_back({name, ok});
    return rows;
}

class FormatsCorpus : public ::testing::TestWithParam<IndexRow> {};

TEST_P(FormatsCorpus, ReadOrRejectAsIndexSays) {
    const auto& row = GetParam();
    const std::string path = (test::formats_dir() / row.file).string();
    std::string error;
    try {
        auto file = io::File::open(path);
        auto tile = dataset::read_tile(file);
        EXPECT_EQ(tile.path(), path);
    } catch (const Error& e) {
        error = e.what();
        EXPECT_EQ(e.file(), path);
        EXPECT_EQ(error.find('\n'), std::string::npos) << "an error is one line";
        EXPECT_GT(e.cause().size(), 10u);
    }
    if (row.decodes) EXPECT_EQ(error, "") << row.file;
    else EXPECT_NE(error, "") << row.file << " must be rejected";
}

std::string row_name(const ::testing::TestParamInfo<IndexRow>& info) {
    std::string s = info.param.file;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Index, FormatsCorpus, ::testing::ValuesIn(index_rows()), row_name);

TEST(FormatsCorpusIndex, ListsEveryFile) {
    auto rows = index_rows();
    EXPECT_EQ(rows.size(), 155u);
    std::size_t on_disk = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(test::formats_dir())) {
        const bool expected_output = e.path().parent_path().filename() == "expected";
        if (e.is_regular_file() && !expected_output && e.path().filename() != "INDEX.md") ++on_disk;
    }
    EXPECT_EQ(on_disk, rows.size());
}

}  // namespace
}  // namespace lidarscout
