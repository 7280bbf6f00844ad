// bench_polygon [--points N] [--runs N]
// The point-in-polygon test of clip and the area tool (core/polygon.hpp) as the vertex count grows: a
// square, circles of 1k, 100k and 10M vertices (radii varying by a sixth of the vertex spacing); then,
// with a twentieth of the points, stress shapes whose horizontal lines cross many edges: a zigzag
// circle (every edge a 20-unit spike) and stars of 100k vertices whose spikes reach from half the
// radius (or from near the centre) to the rim. For each: seconds to build the polygon and its index,
// then N random points over the polygon's box (default 1,000,000) tested, median of --runs (default
// 3); edges examined per point, index entries per vertex, bytes the polygon holds (vertices and index), and the
// share of points inside.
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/polygon.hpp"
#include "polygon_shapes.hpp"

using namespace lidarscout;

namespace {

template <typename Make>
void run(const std::string& name, Make make, std::size_t points, int runs) {
    std::mt19937 rng(1);
    Ring ring = make();
    const auto t0 = bench::Clock::now();
    const MultiPolygon p({{std::move(ring)}});
    const double build_s = bench::seconds_since(t0), held = static_cast<double>(p.held_bytes());
    std::uniform_real_distribution<double> ux(p.min_x(), p.max_x()), uy(p.min_y(), p.max_y());
    std::vector<XY> xy(points);
    for (XY& v : xy) v = {ux(rng), uy(rng)};
    std::vector<double> seconds;
    std::size_t inside = 0, examined = 0;
    for (int r = 0; r < runs; ++r) {
        const auto t1 = bench::Clock::now();
        inside = 0;
        for (const XY& v : xy) inside += p.contains(v.x, v.y);
        seconds.push_back(bench::seconds_since(t1));
    }
    for (const XY& v : xy) examined += p.edges_examined(v.x, v.y);
    const double n = static_cast<double>(points), vertices = static_cast<double>(p.vertex_count());
    fmt::print("{:<28} build {:7.3f} s  {} points {:7.3f} s  edges/point {:9.1f}  entries/vertex {:4.2f}  "
               "held {:7.1f} MB ({:2.0f} B/vertex)  inside {:4.1f} %\n",
               name, build_s, points, bench::median(seconds), static_cast<double>(examined) / n,
               static_cast<double>(p.index_entries()) / vertices, held / 1e6,
               held / vertices, 100.0 * static_cast<double>(inside) / n);
}

}  // namespace

int main(int argc, char** argv) {
    return bench::bench_main("bench_polygon", "[--points N] [--runs N]", argc, argv, [](int argc, char** argv) {
        std::size_t points = 1'000'000;
        int runs = 3;
        for (int i = 1; i + 1 < argc; i += 2) {
            const std::string a = argv[i];
            if (a == "--points") points = std::stoul(argv[i + 1]);
            else if (a == "--runs") runs = std::max(1, std::stoi(argv[i + 1]));
            else throw std::invalid_argument(a);
        }
        std::mt19937 rng(2);
        std::uniform_real_distribution<double> noise(0, 1);
        const auto shape = [](std::size_t n, auto r) { return [n, r] { return test::radial_ring(n, r); }; };
        // Outlines: radii varying by a sixth of the vertices' spacing (2 pi 1000 / n).
        const auto circle = [&](std::size_t n) {
            return shape(n, [&, n](std::size_t) { return 1000 + 1e3 / static_cast<double>(n) * noise(rng); });
        };
        // Stress: a zigzag of radii 1000..1020 (every edge a spike), and stars.
        const auto jagged = [&](std::size_t n) {
            return shape(n, [&](std::size_t) { return 1000 + 20 * noise(rng); });
        };
        const auto star = [&](std::size_t n, double inner) {
            return shape(n, [inner](std::size_t i) { return i % 2 ? inner : 1000.0; });
        };
        run("square (4 vertices)", shape(4, [](std::size_t) { return 1000.0; }), points, runs);
        run("circle (1k)", circle(1000), points, runs);
        run("circle (100k)", circle(100'000), points, runs);
        run("circle (10M)", circle(10'000'000), points, runs);
        fmt::print("stress shapes, {} points:\n", points / 20);
        run("zigzag 1000..1020 (100k)", jagged(100'000), points / 20, runs);
        run("star 500..1000 (100k)", star(100'000, 500), points / 20, runs);
        run("star 1..1000 (100k)", star(100'000, 1), points / 20, runs);
        return 0;
    });
}
