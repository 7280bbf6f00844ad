// bench_dem [PATH...] [--texel M] [--runs N] [--threads N] [--gdal-grid] [--overview linear|cnn]
//           [--product dtm,dsm,chm [--classes 2,9]]
// Times `dem --from full --method mean` (gridding + COG, median of --runs) on a dataset
// (default ../shared/data/surveys/ky-jmo335-eastern-kentucky), or `--from overview` with
// --overview. With --product it also times `dem --product LIST` (one read of the points for all),
// each run right after a run of the plain DEM, and prints both medians and their ratio (--classes:
// the dtm's, as `dem --product --classes`). With
// --gdal-grid it also writes the same points as CSV (in the CRS's units) and grids them with
// gdal-bin's `gdal_grid -a average` (search radius half a texel, the circle inscribed in our
// square texel) on the same grid, timed once, and prints the speed ratio and
// how the two rasters compare: texels where both have a value, and how many agree within
// float rounding (they differ where points fall in a texel's corners, outside the circle).
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "raster/dem.hpp"

namespace fs = std::filesystem;
using namespace lidarscout;
using bench::Clock;
using bench::median;
using bench::seconds_since;

namespace {

// User + system CPU seconds of this process (RUSAGE_SELF) or of its finished children.
double cpu_seconds(int who) {
    rusage u{};
    getrusage(who, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Every point as "x,y,z" in the frame's native units, plus the OGR VRT that gdal_grid reads.
std::string write_points_csv(const dataset::Dataset& ds, const fs::path& dir) {
    const fs::path csv = dir / "points.csv", vrt = dir / "points.vrt";
    FILE* f = std::fopen(csv.c_str(), "w");
    std::fprintf(f, "x,y,z\n");
    ThreadPool pool(std::max(1u, std::thread::hardware_concurrency()));
    const double xy = ds.frame.xy_to_metres, z = ds.frame.z_to_metres;
    for (std::uint32_t t = 0; t < ds.tiles.size(); ++t) {
        dataset::for_each_metric_batch(ds, t, pool, [&](std::uint64_t, std::span<const dataset::MetricPoint> pts) {
            for (const auto& p : pts) std::fprintf(f, "%.6f,%.6f,%.6f\n", p.x / xy, p.y / xy, p.z / z);
        }, las::fields::kXyz);
    }
    std::fclose(f);
    FILE* v = std::fopen(vrt.c_str(), "w");
    std::fprintf(
        v,
        "<OGRVRTDataSource><OGRVRTLayer name=\"points\"><SrcDataSource>%s</SrcDataSource>"
        "<GeometryType>wkbPoint25D</GeometryType>"
        "<GeometryField encoding=\"PointFromColumns\" x=\"x\" y=\"y\" z=\"z\"/></OGRVRTLayer></OGRVRTDataSource>\n",
        csv.c_str());
    std::fclose(v);
    return vrt.string();
}

struct Raster {
    int width = 0, height = 0;
    std::vector<float> values;
};

// Reads band 1 through gdal_translate to raw float32 (no GDAL linking in the benchmarks).
Raster read_float_raster(const std::string& tif, const fs::path& dir, int width, int height) {
    const std::string raw = (dir / "read.bin").string();
    const std::string cmd = fmt::format("gdal_translate -q -of ENVI -ot Float32 '{}' '{}'", tif, raw);
    Raster r{width, height, std::vector<float>(static_cast<std::size_t>(width) * height)};
    if (std::system(cmd.c_str()) != 0) return {};
    FILE* f = std::fopen(raw.c_str(), "rb");
    const std::size_t n = f ? std::fread(r.values.data(), sizeof(float), r.values.size(), f) : 0;
    if (f) std::fclose(f);
    if (n != r.values.size()) return {};
    return r;
}

}  // namespace

namespace {

int run(int argc, char** argv) {
    std::vector<std::string> paths;
    double texel = 1.0;
    int runs = 5;
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    bool gdal_grid = false;
    std::string overview, products, classes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--texel" && i + 1 < argc) texel = std::stod(argv[++i]);
        else if (a == "--runs" && i + 1 < argc) runs = std::stoi(argv[++i]);
        else if (a == "--threads" && i + 1 < argc) threads = static_cast<unsigned>(std::stoul(argv[++i]));
        else if (a == "--overview" && i + 1 < argc) overview = argv[++i];
        else if (a == "--product" && i + 1 < argc) products = argv[++i];
        else if (a == "--classes" && i + 1 < argc) classes = argv[++i];
        else if (a == "--gdal-grid") gdal_grid = true;
        else paths.push_back(a);
    }
    if (paths.empty()) paths.push_back(std::string(LIDARSCOUT_DATA_DIR) + "/surveys/ky-jmo335-eastern-kentucky");
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_bench_dem_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const dataset::Dataset ds = dataset::open_dataset(paths);
    raster::DemRequest r;
    r.output = (dir / "dem.tif").string();
    r.texel_m = texel;
    r.threads = threads;
    if (!overview.empty()) {
        r.source = raster::DemSource::Overview;
        r.method = raster::dem_method_from_name(overview, r.source);
    }
    raster::DemRequest pr = r;
    pr.output = (dir / "product.tif").string();
    if (!products.empty()) pr.products = raster::products_from_names(products);
    if (!classes.empty()) pr.product_options.dtm_classes = PointFilter::parse(classes, "", "");
    std::vector<double> seconds, product_seconds, product_cpu;
    raster::DemResult result, product_result;
    double ours_cpu = 0;
    for (int k = 0; k < runs; ++k) {
        double cpu0 = cpu_seconds(RUSAGE_SELF);
        auto t0 = Clock::now();
        result = raster::make_dem(ds, r);
        seconds.push_back(seconds_since(t0));
        ours_cpu += (cpu_seconds(RUSAGE_SELF) - cpu0) / std::max(1, runs);
        if (products.empty()) continue;
        cpu0 = cpu_seconds(RUSAGE_SELF);
        t0 = Clock::now();
        product_result = raster::make_dem(ds, pr);
        product_seconds.push_back(seconds_since(t0));
        product_cpu.push_back(cpu_seconds(RUSAGE_SELF) - cpu0);
    }
    const double ours = median(seconds);
    std::printf("dem %s (%s): %zu tiles, %llu points, %d x %d texels of %g m, %u threads\n",
                overview.empty() ? "full" : "overview", std::string(raster::dem_method_name(r.method)).c_str(),
                ds.tiles.size(), (unsigned long long)ds.point_count, result.grid.width, result.grid.height, texel,
                threads);
    std::printf(
        "  median of %d: %.3f s (last run: gridding %.3f s, COG %.3f s), %.1f M points/s, peak %zu blocks, "
        "%.2f CPU s per run\n",
        runs, ours, result.seconds_grid, result.seconds_cog, ds.point_count / ours / 1e6, result.peak_blocks, ours_cpu);
    if (!products.empty()) {
        const double p = median(product_seconds);
        std::printf("dem --product %s: median of %d: %.3f s (last run: gridding %.3f s, COG %.3f s), %.2f CPU s per "
                    "run (median), peak %zu blocks; %.2fx the plain DEM\n",
                    products.c_str(), runs, p, product_result.seconds_grid, product_result.seconds_cog,
                    median(product_cpu), product_result.peak_blocks, p / ours);
    }
    std::fflush(stdout);
    if (gdal_grid) {
        const std::string vrt = write_points_csv(ds, dir);
        const auto& g = result.grid;
        const double f = ds.frame.xy_to_metres;
        const std::string out = (dir / "gdal_grid.tif").string();
        const std::string cmd = fmt::format(
            "gdal_grid -q -a average:radius1={0}:radius2={0}:min_points=1:nodata=-9999 -txe {1:.6f} {2:.6f} "
            "-tye {3:.6f} {4:.6f} -outsize {5} {6} -ot Float32 -of GTiff -l points '{7}' '{8}'",
            0.5 * texel / f, g.origin_x / f, (g.origin_x + g.width * texel) / f, (g.origin_y + g.height * texel) / f,
            g.origin_y / f, g.width, g.height, vrt, out);
        const auto t0 = Clock::now();
        const double child0 = cpu_seconds(RUSAGE_CHILDREN);
        const int status = std::system(cmd.c_str());
        const double theirs = seconds_since(t0), theirs_cpu = cpu_seconds(RUSAGE_CHILDREN) - child0;
        if (status != 0) {
            std::fprintf(stderr, "gdal_grid failed (%d): %s\n", status, cmd.c_str());
            return 1;
        }
        const Raster a = read_float_raster(r.output, dir, g.width, g.height);
        const Raster b = read_float_raster(out, dir, g.width, g.height);
        std::size_t both = 0, equal = 0, only_ours = 0, only_theirs = 0;
        for (std::size_t i = 0; i < a.values.size() && i < b.values.size(); ++i) {
            const bool ha = a.values[i] != -9999.0f, hb = b.values[i] != -9999.0f;
            only_ours += ha && !hb;
            only_theirs += hb && !ha;
            if (!ha || !hb) continue;
            ++both;
            equal += std::abs(a.values[i] - b.values[i]) <= 1e-6f * std::max(1.0f, std::abs(a.values[i]));
        }
        std::printf("gdal_grid -a average (radius %.3f): %.1f s, %.1fx slower than ours; %.1f CPU s, %.1fx ours\n",
                    0.5 * texel / f, theirs, theirs / ours, theirs_cpu, theirs_cpu / ours_cpu);
        std::printf("  texels with a value in both: %zu, equal within float rounding: %zu (%.1f%%); only ours: %zu, "
                    "only gdal_grid: %zu\n", both, equal, both ? 100.0 * equal / both : 0.0, only_ours, only_theirs);
    }
    fs::remove_all(dir);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_dem",
                                         "[PATH...] [--texel M] [--runs N] [--threads N] [--gdal-grid] "
                                         "[--overview linear|cnn] [--product dtm,dsm,chm [--classes 2,9]]",
                                         argc, argv, run);
}
