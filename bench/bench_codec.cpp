// Benchmark: LAZ decode and encode speed, warm cache, median of 5 runs.
//   decode points/s: full records, XYZ only, XYZ + RGB (the latter two skip layers of
//   layered files), single-threaded and with all threads; encode points/s likewise.
// Usage: bench_codec FILE.laz... [--runs N] [--mode full|xyz|xyz+rgb|encode] (default: all modes)
//        [--threads N] (default: one thread, then all; one count keeps callgrind runs short)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/chunk_encoder.hpp"
#include "laz/laz.hpp"

using namespace lidarscout;

namespace {

template <typename Fn>
double median_rate(int runs, std::uint64_t items, Fn&& fn) {
    fn();  // warm-up (page cache, allocations)
    std::vector<double> rates;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        rates.push_back(items / std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(rates.begin(), rates.end());
    return rates[rates.size() / 2];
}

void bench_file(const std::string& path, int runs, const std::string& only, unsigned only_threads) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    if (!tile.laz()) {
        fmt::print("{}: not a LAZ file, skipped\n", path);
        return;
    }
    laz::LazLayout layout{tile.header, *tile.laz(),
                          laz::decode_units(tile.header, *tile.laz(), *tile.chunks(), tile.file_size())};
    const std::uint64_t n = tile.header.point_count;
    std::vector<std::uint8_t> records(n * tile.header.record_length);
    fmt::print("{}: {} points, format {}, compressor {}, {} chunks\n", path, n, tile.header.point_format,
               tile.laz()->compressor, layout.units.size());
    const unsigned all = std::max(1u, std::thread::hardware_concurrency());
    struct Mode {
        const char* name;
        std::uint32_t fields;
    };
    const Mode modes[] = {
        {"full", las::fields::kAll}, {"xyz", las::fields::kXyz}, {"xyz+rgb", las::fields::kXyz | las::fields::kRgb}};
    for (unsigned threads : {1u, all}) {
        if (only_threads != 0 && threads != only_threads) continue;
        ThreadPool pool(threads);
        for (const auto& m : modes) {
            if (!only.empty() && only != m.name) continue;
            const double rate = median_rate(runs, n, [&] {
                laz::decode_units_parallel(file, layout, 0, layout.units.size(), records, m.fields, pool);
            });
            fmt::print("  decode {:<8} threads {}: {:8.2f} M points/s\n", m.name, threads, rate / 1e6);
        }
        if (!only.empty() && only != "encode") continue;
        laz::decode_units_parallel(file, layout, 0, layout.units.size(), records, las::fields::kAll, pool);
        std::vector<std::vector<std::uint8_t>> encoded(layout.units.size());
        const double rate = median_rate(runs, n, [&] {
            pool.for_each(layout.units.size(), [&](std::size_t k) {
                const auto& c = layout.units[k];
                encoded[k].clear();
                laz::encode_chunk(*tile.laz(),
                                  std::span(records).subspan(c.first_point * tile.header.record_length,
                                                             c.point_count * tile.header.record_length),
                                  c.point_count, encoded[k]);
            });
        });
        fmt::print("  encode          threads {}: {:8.2f} M points/s\n", threads, rate / 1e6);
    }
}

}  // namespace

namespace {

int run(int argc, char** argv) {
    int runs = 5;
    std::string only;
    unsigned only_threads = 0;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--mode") == 0 && i + 1 < argc) only = argv[++i];
        else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) only_threads = std::atoi(argv[++i]);
        else files.push_back(argv[i]);
    }
    if (files.empty()) {
        fmt::print(stderr,
                   "usage: bench_codec FILE.laz... [--runs N] [--mode full|xyz|xyz+rgb|encode] [--threads N]\n");
        return 2;
    }
    for (const auto& f : files) {
        try {
            bench_file(f, runs, only, only_threads);
        } catch (const Error& e) {
            fmt::print(stderr, "{}\n", e.what());
            return 1;
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_codec",
                                         "FILE.laz... [--runs N] [--mode full|xyz|xyz+rgb|encode] [--threads N]",
                                         argc, argv, run);
}
