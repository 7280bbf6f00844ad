// Benchmark: the TIN walk of recon/local_delaunay.hpp, one thread, warm cache. For random points at
// several densities (points per texel) over a 512-texel window, the thread CPU ns per texel of
// building the buckets and of finding every texel centre's Delaunay triangle (walks chained along
// rows below 4 points a texel, as the dtm does), median of 5 runs.
// Usage: bench_tin [TEXELS [POINTS_PER_TEXEL]]   (default 512, five densities from 0.5 to 60)
#include <fmt/format.h>
#include <time.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "recon/grid_geometry.hpp"
#include "recon/local_delaunay.hpp"

using namespace lidarscout;
using namespace lidarscout::recon;

namespace {

double thread_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e9 + ts.tv_nsec;
}

// Distinct random grid positions sorted by (y, x), as a patch gives them.
std::vector<GridXY> random_positions(std::size_t count, std::int64_t extent, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::int64_t> u(0, extent);
    std::vector<GridXY> out(count);
    for (auto& p : out) p = {double(u(rng)), double(u(rng))};
    const auto by_y_then_x = [](const GridXY& a, const GridXY& b) { return a.y < b.y || (a.y == b.y && a.x < b.x); };
    std::sort(out.begin(), out.end(), by_y_then_x);
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

struct Figures {
    double build_ns = 0, walk_ns = 0;  // per texel
    std::size_t valued = 0;
};

Figures run_once(const std::vector<GridXY>& points, int texels, std::int64_t extent, bool chained) {
    Figures f;
    const double t0 = thread_ns();
    const LocalDelaunay local(points, extent);
    const double t1 = thread_ns();
    LocalDelaunay::Hint hint;
    for (int row = 0; row < texels; ++row) {
        hint.has_last = false;
        for (int col = 0; col < texels; ++col) {
            const GridXY q{texel_centre(col), texel_centre(row)};
            const auto found = local.triangle_at(q, 0.0, chained ? &hint : nullptr);
            f.valued += found.answer == LocalDelaunay::Answer::Triangle;
        }
    }
    const double t2 = thread_ns(), n = double(texels) * texels;
    f.build_ns = (t1 - t0) / n, f.walk_ns = (t2 - t1) / n;
    return f;
}

}  // namespace

int run(int argc, char** argv) {
    const int texels = argc > 1 ? std::stoi(argv[1]) : 512;
    if (texels < 8 || texels > 1024) throw Error("TEXELS must be 8 .. 1024");
    const std::int64_t extent = std::int64_t{texels} * kGridUnitsPerTexel;
    std::vector<double> densities{0.5, 1.3, 3.0, 10.0, 60.0};
    if (argc > 2) densities = {std::stod(argv[2])};
    if (!(densities[0] > 0 && densities[0] <= 1000)) throw Error("POINTS_PER_TEXEL must be in (0, 1000]");
    fmt::print("TIN walk over {0} x {0} texels, one thread, ns of thread CPU per texel (median of 5)\n", texels);
    for (const double density : densities) {
        const auto points = random_positions(std::size_t(density * texels * texels), extent, 2025);
        const bool chained = density < 4;
        std::vector<Figures> runs;
        for (int r = 0; r < 6; ++r) runs.push_back(run_once(points, texels, extent, chained));
        runs.erase(runs.begin());  // warm-up
        std::sort(runs.begin(), runs.end(), [](const Figures& a, const Figures& b) { return a.walk_ns < b.walk_ns; });
        const Figures& median = runs[2];
        fmt::print("  {:5.1f} points a texel ({}): build {:6.1f} ns, walk {:7.1f} ns per texel ({} with a value)\n",
                   density, chained ? "chained" : "from the nearest point", median.build_ns, median.walk_ns,
                   median.valued);
    }
    return 0;
}

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_tin", "[TEXELS [POINTS_PER_TEXEL]]", argc, argv, run);
}
