// Option parsing shared by the reconstruction commands (`eval`, `train-data`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dataset/dataset.hpp"
#include "pipelines/region_split.hpp"

namespace CLI {
class App;
}

namespace lidarscout::cli {

// "auto" -> empty; a positive integer -> its value; anything else throws Error.
std::optional<std::uint64_t> parse_stride(const std::string& text);
// "a,b,,c" -> {"a", "b", "", "c"}: the items of a comma-separated option value.
std::vector<std::string> split_commas(const std::string& text);
// "1,2.5,5,10" -> the positive numbers; throws Error otherwise.
std::vector<double> parse_number_list(const std::string& text, const char* option);
// The name a dataset is reported under: the folder's or file's name.
std::string dataset_name(const std::string& path);
// Opens one dataset (a PATH argument), printing its skipped files on stderr; throws Error
// when nothing in it can be read.
dataset::Dataset open_reported_dataset(const std::string& path);
// --split-block, --val-fraction, --split-seed (the region split, pipelines/region_split.hpp).
void add_split_options(CLI::App& cmd, pipelines::RegionSplitOptions& split);
// --offsets N (lattices per texel size, pipelines/survey_samples.hpp).
void add_offsets_option(CLI::App& cmd, int& offsets);

}  // namespace lidarscout::cli
