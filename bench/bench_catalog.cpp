// Benchmark: how fast a STAC catalog (a QGIS .vpc, an ItemCollection, a paged search: a path or URL)
// is read into its items (dataset/stac_catalog.hpp), and what that costs in memory: the median seconds
// of N reads, the items and errors of one, the peak resident memory of the process (which holds the
// items of one read at a time) and the resident memory the items leave.
// Usage: bench_catalog CATALOG [--runs N]   (default 5 runs)
// A 152,100-item catalog: `lidarscout synth replicate TILE OUT --copies ... --virtual`, then
// `lidarscout catalog OUT/replicate.json -o big.vpc` (or the replica server's catalog.vpc / search).
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "dataset/stac_catalog.hpp"

using namespace lidarscout;

namespace {

int run(int argc, char** argv) {
    std::string catalog;
    int runs = 5;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--runs" && i + 1 < argc) {
            runs = std::max(1, std::stoi(argv[++i]));
        } else if (catalog.empty()) {
            catalog = a;
        } else {
            throw Error("unexpected argument '" + a + "'; see --help");
        }
    }
    if (catalog.empty()) throw Error("no catalog given; see --help");
    const std::uint64_t rss_before = resident_bytes();
    std::vector<double> seconds;
    std::size_t items = 0, errors = 0, documents = 0;
    std::uint64_t kept = 0;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = bench::Clock::now();
        const dataset::Catalog c = dataset::read_catalog(catalog);
        seconds.push_back(bench::seconds_since(t0));
        items = c.items.size(), errors = c.errors.size(), documents = c.documents;
        kept = resident_bytes() - std::min(resident_bytes(), rss_before);
        if (errors != 0 && r == 0) fmt::print("first error: {}\n", c.errors.front());
    }
    fmt::print("catalog {}: {} items, {} errors, {} documents\n", catalog, items, errors, documents);
    fmt::print("read: median {:.3f} s of {} runs (min {:.3f} s)\n", bench::median(seconds), runs,
               *std::min_element(seconds.begin(), seconds.end()));
    fmt::print("memory: peak RSS {:.1f} MB (before reading {:.1f} MB; the items held {:.1f} MB)\n",
               peak_resident_bytes() / 1e6, rss_before / 1e6, kept / 1e6);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bench::bench_main("bench_catalog", "CATALOG [--runs N]", argc, argv, run);
}
