// Benchmark: the overview of a dataset at disk speed (issue 4).
//   1. the device's own ceiling, measured in the same run: random 4 KiB reads/s over the
//      dataset's files at 32 in flight, O_DIRECT (cold) and from the page cache (warm);
//   2. headers + chunk tables of every tile: seconds, cold (page cache dropped, needs root)
//      and warm;
//   3. chunk points per second into the patch grid: cold (page cache dropped; and O_DIRECT)
//      and warm, for each back end.
// Every figure is the median of --runs runs (default 5).
// Usage: bench_scan [--runs N] [--backend auto|io_uring|pread] PATH...
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"
#include "core/patch_grid.hpp"
#include "io/batch_reader.hpp"

using namespace lidarscout;

namespace {

using bench::Clock;
using bench::median;
using bench::seconds_since;

// Drops the page cache (root only); false when not allowed.
bool drop_page_cache() {
    ::sync();
    std::ofstream f("/proc/sys/vm/drop_caches");
    if (!f) return false;
    f << "3\n";
    f.flush();
    return static_cast<bool>(f);
}

// `count` reads of 4 KiB, each of a sector drawn from `sectors` (fd, offset).
class RandomSectors final : public io::ReadSource {
public:
    RandomSectors(const std::vector<std::pair<int, std::uint64_t>>& sectors, std::size_t count, std::uint64_t seed) {
        std::mt19937_64 rng(seed);
        for (std::size_t i = 0; i < count; ++i) {
            const auto& [fd, offset] = sectors[rng() % sectors.size()];
            requests_.push_back({fd, offset, 4096, i});
        }
    }
    std::size_t next(std::span<io::ReadRequest> out) override {
        std::lock_guard lock(mutex_);
        std::size_t n = 0;
        while (n < out.size() && next_ < requests_.size()) out[n++] = requests_[next_++];
        return n;
    }
    void complete(const io::ReadRequest&, std::span<const std::uint8_t>, const ErrorRecord*) override {}

private:
    std::mutex mutex_;
    std::vector<io::ReadRequest> requests_;
    std::size_t next_ = 0;
};

double run_sector_reads(const std::vector<std::pair<int, std::uint64_t>>& sectors, std::size_t count, bool direct,
                        std::uint64_t seed) {
    RandomSectors source(sectors, count, seed);
    io::BatchReadOptions opt;
    opt.backend = io::ReadBackend::IoUring;
    opt.threads = 1;
    opt.queue_depth = 32;
    opt.direct = direct;
    const auto t0 = Clock::now();
    io::run_batch_reads(source, opt);
    return count / seconds_since(t0);
}

// Random 4 KiB reads at 32 in flight: from the device (O_DIRECT, anywhere in the files), or
// from the page cache (a set of 50,000 sectors read once before the timed run).
double random_read_rate(const dataset::Dataset& ds, bool direct, std::size_t count) {
    std::vector<int> fds;
    std::vector<std::pair<int, std::uint64_t>> sectors;
    std::mt19937_64 rng(42);
    for (const auto& t : ds.tiles) {
        const int fd = ::open(t.tile.path().c_str(), O_RDONLY | (direct ? O_DIRECT : 0));
        if (fd < 0) continue;
        fds.push_back(fd);
        const std::uint64_t n = std::max<std::uint64_t>(1, t.tile.file_size() / 4096);
        const std::size_t per_file = direct ? 64 : 50'000 / ds.tiles.size() + 1;
        for (std::size_t i = 0; i < per_file; ++i) sectors.emplace_back(fd, (rng() % n) * 4096);
    }
    if (!direct) run_sector_reads(sectors, sectors.size() * 3, false, 1);  // bring them into the cache
    const double rate = run_sector_reads(sectors, count, direct, 2);
    for (int fd : fds) ::close(fd);
    return rate;
}

struct LoadResult {
    double rate = 0;
    std::uint64_t points = 0;
};

LoadResult load_chunk_points(const dataset::Dataset& ds, io::ReadBackend backend, bool direct) {
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    dataset::ChunkPointLoaderOptions opt;
    opt.reads.backend = backend;
    opt.direct_io = direct;
    dataset::ChunkPointLoader loader(ds, grid, opt);
    const auto t0 = Clock::now();
    loader.start();
    loader.wait();
    const double s = seconds_since(t0);
    if (loader.failed() > 0) {
        fmt::print(stderr, "warning: {} chunk points failed: {}\n", loader.failed(), loader.errors().front().message());
    }
    return {loader.loaded() / s, loader.loaded()};
}

}  // namespace

namespace {

int run(int argc, char** argv) {
    std::vector<std::string> paths;
    int runs = 5;
    std::string backend_name = "auto";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (a == "--backend" && i + 1 < argc) backend_name = argv[++i];
        else paths.push_back(a);
    }
    if (paths.empty()) {
        fmt::print(stderr, "usage: bench_scan [--runs N] [--backend auto|io_uring|pread] PATH...\n");
        return 2;
    }
    const io::ReadBackend backend = backend_name == "pread" ? io::ReadBackend::Pread
                                    : backend_name == "io_uring" ? io::ReadBackend::IoUring
                                                                 : io::ReadBackend::Auto;
    try {
        const bool can_drop = drop_page_cache();
        auto ds = dataset::open_dataset(paths);
        fmt::print("dataset: {} tiles ({} skipped), {} points, {} chunk points\n", ds.tiles.size(), ds.skipped.size(),
                   ds.point_count, ds.chunk_point_count);
        fmt::print("page cache drop: {}\n",
                   can_drop ? "yes (cold figures are cold)" : "NOT ALLOWED (cold = O_DIRECT only)");

        std::vector<double> cold_h, warm_h, dev_cold, dev_warm, cp_cold, cp_direct, cp_warm;
        for (int r = 0; r < runs; ++r) {
            if (can_drop) {
                drop_page_cache();
                auto t0 = Clock::now();
                ds = dataset::open_dataset(paths);
                cold_h.push_back(seconds_since(t0));
                drop_page_cache();
                cp_cold.push_back(load_chunk_points(ds, backend, false).rate);
            }
            dev_cold.push_back(random_read_rate(ds, true, 100'000));
            cp_direct.push_back(load_chunk_points(ds, backend, true).rate);
            ds = dataset::open_dataset(paths);  // make sure the headers are cached
            auto t0 = Clock::now();
            ds = dataset::open_dataset(paths);
            warm_h.push_back(seconds_since(t0));
            load_chunk_points(ds, backend, false);  // make sure the chunk points are cached
            cp_warm.push_back(load_chunk_points(ds, backend, false).rate);
            dev_warm.push_back(random_read_rate(ds, false, 400'000));
        }
        fmt::print("median of {} runs, back end {}:\n", runs, backend_name);
        fmt::print("  device random 4 KiB reads, QD32 O_DIRECT:  {:>10.0f} /s\n", median(dev_cold));
        fmt::print("  page-cache random 4 KiB reads, QD32:       {:>10.0f} /s\n", median(dev_warm));
        if (can_drop) fmt::print("  headers + chunk tables, cold:              {:>10.3f} s\n", median(cold_h));
        fmt::print("  headers + chunk tables, warm:              {:>10.3f} s\n", median(warm_h));
        if (can_drop) {
            fmt::print("  chunk points, cold (cache dropped):        {:>10.0f} /s  ({:.0f}% of device)\n",
                       median(cp_cold), 100 * median(cp_cold) / median(dev_cold));
        }
        fmt::print("  chunk points, cold (O_DIRECT):             {:>10.0f} /s  ({:.0f}% of device)\n",
                   median(cp_direct), 100 * median(cp_direct) / median(dev_cold));
        fmt::print("  chunk points, warm:                        {:>10.0f} /s  ({:.0f}% of page cache)\n",
                   median(cp_warm), 100 * median(cp_warm) / median(dev_warm));
    } catch (const Error& e) {
        fmt::print(stderr, "bench_scan: {}\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_scan",
                                         "[--runs N] [--backend auto|io_uring|pread] PATH...",
                                         argc, argv, run);
}
