// Benchmark: how fast we read what the overview needs, warm cache.
//   headers + VLRs + chunk tables per second (files/s) and chunk points per second,
//   single-threaded and with all threads; median of 5 runs after one warm-up run.
// Usage: bench_metadata [PATH...]   (default: ../shared/data)
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/file_search.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"

using namespace lidarscout;

namespace {

struct RunResult {
    double seconds = 0;
    std::uint64_t items = 0;
};

template <typename Fn>
RunResult timed(std::size_t n, unsigned threads, Fn&& per_item) {
    std::atomic<std::uint64_t> items{0};
    auto t0 = std::chrono::steady_clock::now();
    ThreadPool pool(threads);
    pool.for_each(n, [&](std::size_t i) {
        try {
            items += per_item(i);
        } catch (const Error&) {
            // broken files of the corpus count as read (their header was still parsed)
        }
    });
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), items.load()};
}

template <typename Fn>
void report(const char* what, const char* unit, std::size_t n, unsigned threads, Fn&& per_item) {
    timed(n, threads, per_item);  // warm-up
    std::vector<double> rates;
    std::uint64_t items = 0;
    for (int r = 0; r < 5; ++r) {
        auto res = timed(n, threads, per_item);
        items = res.items;
        rates.push_back(res.items / res.seconds);
    }
    std::sort(rates.begin(), rates.end());
    fmt::print("{:<34} threads {:>2}: {:>12.0f} {}/s (median of 5; {} {} per run; min {:.0f}, max {:.0f})\n", what,
               threads, rates[2], unit, items, unit, rates.front(), rates.back());
}

}  // namespace

namespace {

int run(int argc, char** argv) {
    std::vector<std::string> paths(argv + 1, argv + argc);
    if (paths.empty()) paths.push_back(LIDARSCOUT_DATA_DIR);
    auto files = dataset::find_point_cloud_files(paths).files;
    fmt::print("{} LAS/LAZ files under {}\n", files.size(), fmt::join(paths, " "));

    // Tiles read once for the chunk point runs (which then time only the point reads).
    std::vector<io::File> handles;
    std::vector<dataset::Tile> tiles;
    for (const auto& path : files) {
        try {
            auto f = io::File::open(path);
            auto t = dataset::read_tile(f);
            handles.push_back(std::move(f));
            tiles.push_back(std::move(t));
        } catch (const Error&) {
        }
    }
    fmt::print("{} of them readable\n", tiles.size());

    auto headers = [&](std::size_t i) -> std::uint64_t {
        auto f = io::File::open(files[i]);
        (void)dataset::read_tile(f);
        return 1;
    };
    auto chunk_points = [&](std::size_t i) -> std::uint64_t {
        return dataset::read_chunk_points(handles[i], tiles[i]).size();
    };
    for (unsigned threads : {1u, std::max(1u, std::thread::hardware_concurrency())}) {
        report("headers + VLRs + chunk tables", "files", files.size(), threads, headers);
        report("chunk points (one pread each)", "points", tiles.size(), threads, chunk_points);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_metadata", "[PATH...]   (default: ../shared/data)", argc, argv, run);
}
