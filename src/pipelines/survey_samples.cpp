// sample_survey and its helpers: the stride rule, the patch lattice, candidate patches and
// the one streaming pass over a survey's tiles.
#include "pipelines/survey_samples.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "io/file.hpp"

namespace lidarscout::pipelines {

double point_density(const dataset::Dataset& ds) {
    std::vector<double> densities;
    for (const auto& t : ds.tiles) {
        const auto& b = t.bounds_m;
        const double area = (b.max_x - b.min_x) * (b.max_y - b.min_y);
        if (t.tile.header.point_count > 0 && area > 0) densities.push_back(t.tile.header.point_count / area);
    }
    if (densities.empty()) return 0.0;
    std::nth_element(densities.begin(), densities.begin() + densities.size() / 2, densities.end());
    return densities[densities.size() / 2];
}

std::uint64_t auto_stride(const dataset::Dataset& ds, const PatchSpec& spec) {
    const double per_chunk_point_m2 = kReferenceChunkPoints / kReferenceDensity;  // 2,500 m^2
    const double window_m2 = spec.window_m() * spec.window_m();
    const double k = point_density(ds) * window_m2 / (kReferenceWindowM * kReferenceWindowM / per_chunk_point_m2);
    return static_cast<std::uint64_t>(std::max(1.0, std::round(k)));
}

Lattice lattice_for(const dataset::Dataset& ds, const PatchSpec& spec) {
    spec.validate();
    const auto [ox, oy] = dataset::patch_grid_origin(ds, spec.patch_m());
    return {spec, ox, oy};
}

std::vector<Lattice> offset_lattices(const Lattice& base, int count) {
    std::vector<Lattice> out;
    for (int k = 0; k < count; ++k) {
        const double shift = base.spec.patch_m() * k / count;
        out.push_back({base.spec, base.origin_x + shift, base.origin_y + shift});
    }
    return out;
}

std::vector<CellKey> candidate_patches(const dataset::Dataset& ds, const Lattice& lattice, std::size_t count,
                                               std::uint64_t seed) {
    const lidarscout::PatchGrid keys(lattice.origin_x, lattice.origin_y, lattice.spec.patch_m());
    std::set<lidarscout::CellKey> cells;
    for (const auto& t : ds.tiles) {
        for (const auto& cp : dataset::read_chunk_points(io::File::open(t.tile.path()), t.tile, ds.las_stride)) {
            double x = cp.point.x, y = cp.point.y, z = cp.point.z;
            t.place(x, y, z);
            cells.insert(keys.cell_of(x, y));
        }
    }
    std::vector<lidarscout::CellKey> out(cells.begin(), cells.end());
    Rng rng(hash_of(seed, 0x70a7c4));
    for (std::size_t i = out.size(); i > 1; --i) std::swap(out[i - 1], out[rng.next() % i]);  // Fisher-Yates
    if (out.size() > count) out.resize(count);
    return out;
}

namespace {

// Gives a batch of tile `tile_id`'s points to every sample (its chunk points and its truth).
void add_batch(SurveySamples& out, std::uint32_t tile_id, std::uint64_t first,
               std::span<const dataset::MetricPoint> points, std::uint64_t& coloured) {
    for (std::size_t k = 0; k < points.size(); ++k) {
        const dataset::MetricPoint& s = points[k];
        coloured += s.coloured;
        const std::uint64_t index = first + k;
        for (auto& sample : out.samples) {
            if (index % sample.stride == 0) {
                sample.chunk_points->add(s.x, s.y, s.z, s.rgb, s.intensity, s.classification, tile_id);
            }
            sample.truth->add(s.x, s.y, s.z, s.rgb);
        }
    }
    out.points += points.size();
}

}  // namespace

SurveySamples sample_survey(const dataset::Dataset& ds, const std::vector<SampleRequest>& requests, ThreadPool& pool,
                            const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    SurveySamples out;
    for (const auto& r : requests) {
        if (r.stride == 0) throw Error("chunk point stride must be positive");
        const auto& l = r.lattice;
        out.samples.push_back({l, r.stride,
                               std::make_unique<lidarscout::PatchGrid>(l.origin_x, l.origin_y, l.spec.patch_m()),
                               std::make_unique<GroundTruth>(l.spec, l.origin_x, l.origin_y, r.patches)});
    }
    std::uint64_t done = 0, coloured = 0;
    std::vector<std::uint32_t> tiles(ds.tiles.size());
    std::iota(tiles.begin(), tiles.end(), 0u);
    const auto add = [&](std::uint32_t tile, std::uint64_t first, std::span<const dataset::MetricPoint> points) {
        add_batch(out, tile, first, points, coloured);
        done += points.size();
        if (progress) progress(done, ds.point_count);
    };
    dataset::for_each_metric_batch(ds, tiles, pool, add, nullptr);
    out.has_rgb = coloured * 2 >= out.points && coloured > 0;
    return out;
}

}  // namespace lidarscout::pipelines
