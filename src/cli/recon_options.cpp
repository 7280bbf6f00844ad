// Parsing of --stride, number lists and dataset names for `eval` and `train-data`.
#include "cli/recon_options.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cli/number_options.hpp"
#include "core/error.hpp"

namespace lidarscout::cli {

std::optional<std::uint64_t> parse_stride(const std::string& s) {
    if (s == "auto") return std::nullopt;
    try {
        std::size_t used = 0;
        const auto v = std::stoull(s, &used);
        if (used == s.size() && v > 0 && s[0] != '-') return v;
    } catch (const std::exception&) {
    }
    throw Error("--stride must be a positive integer or 'auto', not '" + s + "'");
}

std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto end = std::min(text.find(',', start), text.size());
        out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

std::vector<double> parse_number_list(const std::string& text, const char* option) {
    std::vector<double> out;
    for (const std::string& item : split_commas(text)) {
        try {
            std::size_t used = 0;
            const double v = std::stod(item, &used);
            if (used != item.size() || !(v > 0) || !std::isfinite(v)) throw std::invalid_argument(item);
            out.push_back(v);
        } catch (const std::exception&) {
            throw Error(std::string(option) + " expects positive numbers separated by commas, not '" + text + "'");
        }
    }
    return out;
}

std::string dataset_name(const std::string& path) {
    auto p = std::filesystem::path(path);
    if (!p.has_filename()) p = p.parent_path();
    return p.filename().string();
}

dataset::Dataset open_reported_dataset(const std::string& path) {
    auto ds = dataset::open_dataset({path});
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    if (ds.tiles.empty()) throw Error(path, std::nullopt, "no readable tiles");
    return ds;
}

void add_split_options(CLI::App& cmd, pipelines::RegionSplitOptions& split) {
    cmd.add_option("--split-block", split.block_m,
                   "Side of the square regions of the train/validation split, metres (default 2000)")
        ->check(positive_number());
    cmd.add_option("--val-fraction", split.val_fraction, "Fraction of regions held out for validation (default 0.25)")
        ->check(CLI::Range(0.0, 1.0));
    cmd.add_option("--split-seed", split.seed, "Seed of the region split (default 1)");
}

void add_offsets_option(CLI::App& cmd, int& offsets) {
    cmd.add_option("--offsets", offsets, "Lattices per texel size, shifted by 1/N of a patch (default 1)")
        ->check(CLI::Range(1, 64));
}

}  // namespace lidarscout::cli
