// The block gridders of full DEMs: texel statistics, inverse distance weighting, a TIN, and the
// highest point per texel with a TIN through the holes.
#include "raster/block_gridders.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/chunked_vector.hpp"
#include "core/error.hpp"
#include "recon/face_map.hpp"
#include "recon/grid_geometry.hpp"
#include "recon/interpolation.hpp"
#include "recon/local_delaunay.hpp"
#include "recon/texel_counts.hpp"
#include "recon/triangulation.hpp"

namespace lidarscout::raster {

namespace {

std::size_t texel_count(const DemGrid& g) { return static_cast<std::size_t>(g.block) * g.block; }

// Whether a texel mask ([row * block + col], 1: marked) marks any texel.
bool any_marked(const std::vector<char>& mask) { return std::find(mask.begin(), mask.end(), 1) != mask.end(); }

std::uint8_t colour_byte(double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v * 255.0), 0L, 255L)); }

// RGBA planes from per-texel colours in [0, 1] (NaN: no value there).
std::vector<std::uint8_t> rgba_planes(std::size_t n, const auto& colour_of) {
    std::vector<std::uint8_t> out(4 * n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const auto [r, g, b] = colour_of(i);
        if (std::isnan(r)) continue;
        out[i] = colour_byte(r), out[n + i] = colour_byte(g), out[2 * n + i] = colour_byte(b);
        out[3 * n + i] = 255;
    }
    return out;
}

// mean / min / max of the points in each texel.
class StatisticGridder final : public BlockGridder {
public:
    StatisticGridder(const GridderSpec& spec, const DemGrid& grid)
        : spec_(spec), block_(grid.block), texels_(texel_count(grid)) {}

    void add(const dataset::MetricPoint& p, const recon::TexelLocation* own) override {
        if (!own) throw Error::in_stage("dem", "a point was routed to a block it does not fall in (internal error)");
        const double v = spec_.value == GridValue::Intensity ? double(p.intensity) : p.z;
        texels_[static_cast<std::size_t>(own->row) * block_ + own->col].add(v, p.rgb);
    }

    BlockImages finish() override {
        BlockImages out;
        out.heights_m.resize(texels_.size());
        for (std::size_t i = 0; i < texels_.size(); ++i) {
            out.heights_m[i] = spec_.value == GridValue::Count ? static_cast<float>(texels_[i].count)
                                                               : texels_[i].height(spec_.statistic);
        }
        if (spec_.rgb) {
            out.rgba = rgba_planes(texels_.size(), [&](std::size_t i) {
                const auto& t = texels_[i];
                return std::array<float, 3>{t.colour(0), t.colour(1), t.colour(2)};
            });
        }
        return out;
    }

private:
    GridderSpec spec_;
    int block_;
    std::vector<recon::TexelStats> texels_;
};

// Inverse distance weighting within a radius of each texel centre.
class IdwGridder final : public BlockGridder {
public:
    IdwGridder(const GridderSpec& spec, const DemGrid& grid, lidarscout::CellKey block)
        : spec_(spec), texel_(grid.texel_m), n_(grid.block),
          min_x_(grid.origin_x + double(block.ix) * grid.block * grid.texel_m),
          min_y_(grid.origin_y + double(block.iy) * grid.block * grid.texel_m),
          radius_(gridder_reach_m(spec, grid.texel_m)), sums_(texel_count(grid)) {
        if (spec.rgb) colours_.resize(3 * sums_.size());
    }

    void add(const dataset::MetricPoint& p, const recon::TexelLocation*) override {
        const auto [c0, c1] = texel_span(p.x - min_x_);
        const auto [r0, r1] = texel_span(p.y - min_y_);
        const double r2 = radius_ * radius_;
        for (int row = r0; row <= r1; ++row) {
            const double dy = min_y_ + (row + 0.5) * texel_ - p.y;
            for (int col = c0; col <= c1; ++col) {
                const double dx = min_x_ + (col + 0.5) * texel_ - p.x, d2 = dx * dx + dy * dy;
                if (d2 > r2) continue;
                const std::size_t i = static_cast<std::size_t>(row) * n_ + col;
                const double w = weight(d2);
                sums_[i].wz += w * p.z;
                sums_[i].w += w;
                if (!colours_.empty()) {
                    colours_[3 * i] += w * p.rgb.r / 255.0;
                    colours_[3 * i + 1] += w * p.rgb.g / 255.0;
                    colours_[3 * i + 2] += w * p.rgb.b / 255.0;
                }
            }
        }
    }

    BlockImages finish() override {
        BlockImages out;
        const float none = recon::kNoValue;
        out.heights_m.resize(sums_.size());
        for (std::size_t i = 0; i < sums_.size(); ++i) {
            out.heights_m[i] = sums_[i].w > 0 ? static_cast<float>(sums_[i].wz / sums_[i].w) : none;
        }
        if (!colours_.empty()) {
            out.rgba = rgba_planes(sums_.size(), [&](std::size_t i) {
                const double w = sums_[i].w;
                if (!(w > 0)) return std::array<double, 3>{none, none, none};
                return std::array<double, 3>{colours_[3 * i] / w, colours_[3 * i + 1] / w, colours_[3 * i + 2] / w};
            });
        }
        return out;
    }

private:
    struct Sum {
        double wz = 0, w = 0;
    };

    // The texels (inclusive, clipped to the block) whose centres may lie within the radius of
    // offset `d` (metres from the block's min edge).
    std::pair<int, int> texel_span(double d) const {
        const double lo = std::ceil((d - radius_) / texel_ - 0.5), hi = std::floor((d + radius_) / texel_ - 0.5);
        return {static_cast<int>(std::max(lo, 0.0)), static_cast<int>(std::min(hi, double(n_ - 1)))};
    }

    // 1 / d^power; a point on a texel centre gets a weight that outweighs any other (gdal_grid
    // takes its value there).
    double weight(double d2) const {
        const double d2_safe = std::max(d2, 1e-24);
        return spec_.idw_power == 2 ? 1.0 / d2_safe : std::pow(d2_safe, -0.5 * spec_.idw_power);
    }

    GridderSpec spec_;
    double texel_;
    int n_;
    double min_x_, min_y_, radius_;
    std::vector<Sum> sums_;
    std::vector<double> colours_;  // weighted r, g, b sums in [0, 1] per texel
};

// A TIN of the block's points and its margin's, interpolated at the texel centres.
class TinGridder final : public BlockGridder {
public:
    TinGridder(const GridderSpec& spec, const DemGrid& grid, lidarscout::CellKey block)
        : spec_(spec), grid_(grid), margin_(tin_margin_texels(spec, grid.texel_m)),
          min_x_(grid.origin_x + double(block.ix) * grid.block * grid.texel_m),
          min_y_(grid.origin_y + double(block.iy) * grid.block * grid.texel_m) {}

    void add(const dataset::MetricPoint& p, const recon::TexelLocation*) override {
        if (points_.empty()) base_z_ = p.z;
        points_.push_back({p.x, p.y, static_cast<float>(p.z - base_z_), p.rgb});
    }

    BlockImages finish() override { return finish_at(nullptr); }
    std::uint64_t held_points() const override { return points_.size(); }

    int margin() const { return margin_; }  // texels seen on each side beyond the block's

    // The heights (and colours) at the block's texels that `wanted` marks ([row * block + col]; all
    // without it), nodata at the others.
    BlockImages finish_at(const std::vector<char>* wanted) {
        const recon::PatchOptions options = patch_options();
        if (spec_.ground) keep_ground(*spec_.ground);
        BlockImages out = no_values();
        std::vector<char> rest;  // what the thinned walks left to every point
        if (!wanted && thins()) {
            rest = thinned_walks(options, out);
            if (!any_marked(rest)) {
                points_.clear();
                return out;
            }
            wanted = &rest;
        }
        const recon::PatchPoints patch = recon::make_patch_points(expanded(), min_x_, min_y_, options);
        points_.clear();
        if (patch.status != recon::PatchStatus::Ok) return out;
        const double texels = double(patch.size()) * patch.size();
        const bool local = spec_.tin_search == TinSearch::Local ||
                           (spec_.tin_search == TinSearch::Auto &&
                            (wanted || double(patch.points.size()) >= kTinWalkPointsPerTexel * texels));
        if (local && walk(patch, wanted, out)) return out;
        const BlockImages whole = tin_images(patch);  // a walk that did not end (never seen): the whole TIN
        for (std::size_t i = 0; i < out.heights_m.size(); ++i) {
            if (!wanted || (*wanted)[i]) copy_texel(whole, out, i);
        }
        return out;
    }

private:
    // Below this many points per texel a walk starts from the last texel's triangle (on ky-jmo335
    // at 1 m: the three products 10.35 -> 9.70 s), above it from the texel's nearest point (at
    // 10 m, 60 points a texel: 6.55 s against 6.96 from the last triangle).
    static constexpr double kChainedPointsPerTexel = 4;
    // A thinned walk keeps the points within kThinRadius / sqrt(points per texel) texels of a texel
    // centre (at most kThinMaxRadius): about 50 points a texel, so that nearly every triangle over
    // a centre has its circle within that reach.
    static constexpr double kThinRadius = 4, kThinMaxRadius = 0.45;
    // The later thinned walks are skipped when they would see more than this share of the points; a
    // circle is checked for points left out over at most this many texels.
    static constexpr double kThinSecondShare = 0.5, kThinMostClearTexels = 65536;

    recon::PatchOptions patch_options() const {
        recon::PatchOptions options;
        options.spec = {grid_.texel_m, grid_.block, margin_};
        options.min_points = 3;
        options.has_rgb = spec_.rgb;
        return options;
    }

    BlockImages no_values() const {
        BlockImages out;
        out.heights_m.assign(texel_count(grid_), recon::kNoValue);
        if (spec_.rgb) out.rgba.assign(4 * texel_count(grid_), 0);
        return out;
    }

    static void copy_texel(const BlockImages& from, BlockImages& to, std::size_t i) {
        to.heights_m[i] = from.heights_m[i];
        const std::size_t n = to.heights_m.size();
        for (std::size_t c = 0; c < to.rgba.size(); c += n) to.rgba[c + i] = from.rgba[c + i];
    }

    // The TIN of the patch's points (at least 3) at every texel centre of the block.
    BlockImages tin_images(const recon::PatchPoints& patch) const {
        BlockImages out = no_values();
        const recon::Triangulation tri =
            recon::triangulate(recon::grid_positions(patch), patch.spec.grid_extent(), /*pad_corners=*/false);
        const recon::FaceMap map =  // the block's own texels only: the margin's are cropped away
            without_long_edges(tri, recon::build_face_map(tri, patch.size(), margin_));
        recon::Image heights(patch.size(), 1);
        recon::fill_linear(heights, tri, map, recon::height_values(patch));
        const recon::Image block = recon::crop_centre(heights, grid_.block);
        for (std::size_t i = 0; i < out.heights_m.size(); ++i) {
            if (!std::isnan(block.values[i])) out.heights_m[i] = static_cast<float>(patch.to_metres(block.values[i]));
        }
        if (spec_.rgb) out.rgba = colours(patch, tri, map);
        return out;
    }

    // The height (and colour) of `found`'s triangle of `patch` at texel i of `out`.
    void interpolate(const recon::PatchPoints& patch, const recon::LocalTriangle& found, std::size_t i,
                     BlockImages& out) const {
        const auto at = [&](float recon::PatchPoint::*channel) {
            float v = 0;
            for (int k = 0; k < 3; ++k) {
                v += static_cast<float>(found.weights[k]) * patch.points[found.corners[k]].*channel;
            }
            return v;
        };
        out.heights_m[i] = static_cast<float>(patch.to_metres(at(&recon::PatchPoint::h)));
        const std::size_t n = out.heights_m.size();
        if (out.rgba.empty()) return;
        const float r = at(&recon::PatchPoint::r);
        if (std::isnan(r)) return;
        out.rgba[i] = colour_byte(r), out.rgba[n + i] = colour_byte(at(&recon::PatchPoint::g));
        out.rgba[2 * n + i] = colour_byte(at(&recon::PatchPoint::b)), out.rgba[3 * n + i] = 255;
    }

    // The wanted texels (all without `wanted`) of `out`, each texel's triangle found from the points
    // around it (recon/local_delaunay.hpp); false should a walk there not end (never seen).
    bool walk(const recon::PatchPoints& patch, const std::vector<char>* wanted, BlockImages& out) const {
        const int n = grid_.block, m = margin_;
        const recon::LocalDelaunay local(recon::grid_positions(patch), patch.spec.grid_extent());
        // few points a texel: each walk starts where the one of the texel before it (in its row) ended
        const bool chained = double(patch.points.size()) < kChainedPointsPerTexel * double(patch.size()) * patch.size();
        recon::LocalDelaunay::Hint hint;
        for (int row = 0; row < n; ++row) {
            hint.has_last = false;
            for (int col = 0; col < n; ++col) {
                const std::size_t i = static_cast<std::size_t>(row) * n + col;
                if (wanted && !(*wanted)[i]) {
                    hint.has_last = false;
                    continue;
                }
                const recon::GridXY q{recon::texel_centre(col + m), recon::texel_centre(row + m)};
                const auto found = local.triangle_at(q, max_edge_units(), chained ? &hint : nullptr);
                if (found.answer == recon::LocalDelaunay::Answer::Unproven) return false;
                if (found.answer == recon::LocalDelaunay::Answer::Triangle) interpolate(patch, found.triangle, i, out);
            }
        }
        return true;
    }

    double max_edge_units() const { return spec_.tin_max_edge_m / grid_.texel_m * double(recon::kGridUnitsPerTexel); }

    // Whether this block walks a thinned set first (GridderSpec::tin_thinning): an edge limit (which
    // bounds what a "no value" depends on), a walk, and points dense enough to leave most out.
    bool thins() const {
        if (!spec_.tin_thinning || !(spec_.tin_max_edge_m > 0) || spec_.tin_search == TinSearch::Triangulate) {
            return false;
        }
        const double window = grid_.block + 2.0 * margin_;
        return double(points_.size()) >= kTinThinFromPointsPerTexel * window * window;
    }

    // The thinned walks. First over the held points within D (kThinRadius) of the block's texel
    // centres: every point left out is farther than D from every centre, so a triangle whose circle
    // lies within D of its centre is the whole set's (its circle is empty of every point, and the
    // points on it are all kept, so ties fall as they would). A texel with no point within the edge
    // limit E around it, or with all of those on one side of its centre, has no short triangle over
    // it. Then the texels left, over the points of the texels within 2 texels of them, and last
    // within E: a triangle is also proven when no texel outside those holds a point in its circle;
    // and within E a "no value" is the whole set's too, since a triangle over a centre with no edge
    // over E has its corners within E, and a triangle of the whole triangulation is one of any subset
    // that holds its corners. Writes what is proven into `out` and returns the texels left (1) for
    // the walk over every point.
    std::vector<char> thinned_walks(const recon::PatchOptions& options, BlockImages& out) const {
        const int n = grid_.block, m = margin_, side = n + 2 * m;
        const double unit = double(recon::kGridUnitsPerTexel), edge = max_edge_units();
        const recon::GridSnap grid(options.spec, min_x_ - options.spec.pad_m(), min_y_ - options.spec.pad_m());
        std::vector<GridPoint> at(points_.size());
        recon::TexelCounts held(side, unit);
        std::size_t inside = 0, occupied = 0;  // held points in the window, texels holding any
        for (std::size_t i = 0; i < points_.size(); ++i) {
            GridPoint& g = at[i];
            g.inside = grid.snap(points_[i].x, points_[i].y, g.gx, g.gy);
            if (!g.inside) continue;
            g.col = std::min(side - 1, int(g.gx / recon::kGridUnitsPerTexel));
            g.row = std::min(side - 1, int(g.gy / recon::kGridUnitsPerTexel));
            occupied += held.add(g.col, g.row, g.gx, g.gy) == 1;
            ++inside;
        }
        held.summed();
        const int reach_texels = static_cast<int>(std::ceil(edge / unit)) + 1;  // all within E of a centre
        const double density = double(inside) / double(std::max<std::size_t>(occupied, 1));  // where points are
        const double near = std::min(kThinMaxRadius, kThinRadius / std::sqrt(density)) * unit;
        const auto near_centre = [&](const GridPoint& g) {
            if (g.col < m || g.row < m || g.col >= m + n || g.row >= m + n) return false;
            const double dx = g.gx - recon::texel_centre(g.col), dy = g.gy - recon::texel_centre(g.row);
            return dx * dx + dy * dy <= near * near;
        };
        const std::vector<char> all(static_cast<std::size_t>(n) * n, 1);
        const auto unknown = [](const recon::Circle&) { return false; };
        std::vector<char> left =
            proven_walk(options, at, near_centre, unknown, all, near, false, &held, reach_texels, out);
        const auto count = [](const std::vector<char>& v) { return std::uint64_t(std::count(v.begin(), v.end(), 1)); };
        const std::uint64_t after_first = count(left);
        const auto tally = [&] {
            if (!spec_.thinning_tally) return;
            spec_.thinning_tally->blocks += 1, spec_.thinning_tally->first += all.size() - after_first;
            spec_.thinning_tally->later += after_first - count(left), spec_.thinning_tally->whole += count(left);
        };
        if (after_first == 0) {
            tally();
            return left;
        }
        // the texels left, over the points near them: within 2 texels (most triangles near an edge of
        // the survey), then within the edge limit (where "no value" is proven too)
        for (const int texels : {2, reach_texels}) {
            recon::TexelCounts marks(side, unit);
            for (std::size_t i = 0; i < left.size(); ++i) {
                if (left[i]) marks.add(int(i % n) + m, int(i / n) + m, 0, 0);
            }
            marks.summed();
            std::vector<char> seen(static_cast<std::size_t>(side) * side);  // texels within `texels` of one left
            for (int row = 0; row < side; ++row) {
                for (int col = 0; col < side; ++col) {
                    seen[std::size_t(row) * side + col] = marks.around(col, row, texels) > 0;
                }
            }
            const auto near_left = [&](const GridPoint& g) { return seen[std::size_t(g.row) * side + g.col] != 0; };
            const auto seen_points = std::count_if(at.begin(), at.end(), [&](const GridPoint& g) {
                return g.inside && near_left(g);
            });
            if (double(seen_points) > kThinSecondShare * double(inside)) break;
            // a circle is clear of the points left out when no texel beyond those seen has a point in it
            const auto clear = [&](const recon::Circle& c) {
                const auto texel = [&](double v) {  // clamped first: a sliver's circle can be vast
                    return static_cast<int>(std::clamp(std::floor(v / unit), -1.0, double(side)));
                };
                const int c0 = std::max(texel(c.x - c.radius), 0), c1 = std::min(texel(c.x + c.radius), side - 1);
                const int r0 = std::max(texel(c.y - c.radius), 0), r1 = std::min(texel(c.y + c.radius), side - 1);
                if (double(c1 - c0 + 1) * (r1 - r0 + 1) > kThinMostClearTexels) return false;
                for (int row = r0; row <= r1; ++row) {
                    for (int col = c0; col <= c1; ++col) {
                        const bool out_of_sight = !seen[std::size_t(row) * side + col];
                        if (out_of_sight && held.meets_disc(col, row, c.x, c.y, c.radius)) return false;
                    }
                }
                return true;
            };
            const bool none_proven = texels == reach_texels;
            left = proven_walk(options, at, near_left, clear, left, (texels - 0.5) * unit, none_proven, nullptr,
                               reach_texels, out);
            if (!any_marked(left)) break;
        }
        tally();
        return left;
    }

    // Where a held point falls in the window: its grid position and texel.
    struct GridPoint {
        std::int32_t gx = 0, gy = 0;
        int col = 0, row = 0;
        bool inside = false;
    };

    // The wanted texels walked over the held points `keep` selects, a set that holds every point
    // within `reach` grid units of each wanted centre: a triangle is written to `out` when its circle
    // lies within that reach or `clear` finds it empty of the points left out. A texel has no value
    // for certain when `held` (given to the first walk only: the texels it leaves fail its test)
    // shows no point within `reach_texels` (the edge limit's reach) of it or all of them on one side
    // of it, or, with `none_proven` (a reach of the edge limit), when the walk finds none. Returns
    // the texels left.
    template <typename Keep, typename Clear>
    std::vector<char> proven_walk(const recon::PatchOptions& options, const std::vector<GridPoint>& at,
                                  const Keep& keep, const Clear& clear, const std::vector<char>& wanted, double reach,
                                  bool none_proven, const recon::TexelCounts* held, int reach_texels,
                                  BlockImages& out) const {
        std::vector<lidarscout::OverviewPoint> kept;
        for (std::size_t i = 0; i < at.size(); ++i) {
            if (at[i].inside && keep(at[i])) kept.push_back(expanded(points_[i]));
        }
        const recon::PatchPoints patch = recon::make_patch_points(kept, min_x_, min_y_, options);
        std::vector<lidarscout::OverviewPoint>().swap(kept);
        if (patch.status != recon::PatchStatus::Ok) return wanted;
        const int n = grid_.block, m = margin_;
        const recon::LocalDelaunay local(recon::grid_positions(patch), patch.spec.grid_extent());
        std::vector<char> left(wanted.size(), 0);
        for (std::size_t i = 0; i < wanted.size(); ++i) {
            if (!wanted[i]) continue;
            const int col = int(i % n) + m, row = int(i / n) + m;
            const recon::GridXY q{recon::texel_centre(col), recon::texel_centre(row)};
            const auto found = local.triangle_at(q, max_edge_units());
            if (found.answer == recon::LocalDelaunay::Answer::Triangle) {
                const auto& c = found.triangle.corners;
                const recon::Circle circle =
                    recon::circumcircle(patch.points[c[0]].xy(), patch.points[c[1]].xy(), patch.points[c[2]].xy());
                if (recon::circle_within(circle, q, reach) || clear(circle)) {
                    interpolate(patch, found.triangle, i, out);
                    continue;
                }
            }
            const bool none = found.answer == recon::LocalDelaunay::Answer::None;
            const bool empty_around =
                held && (held->around(col, row, reach_texels) == 0 || held->beside(col, row, reach_texels));
            left[i] = (none && none_proven) || empty_around ? 0 : 1;
        }
        return left;
    }

    // A point as held until the block is finished: 24 bytes instead of 48. The position stays
    // exact (every block sees the same coordinates, so ties between Delaunay triangulations are
    // broken alike); the height is kept from the first point's, in float (well under 0.1 mm).
    struct Held {
        double x, y;
        float dz;
        lidarscout::Rgb8 rgb;
    };

    // Drops the held points the ground filter does not find on the ground of the block and its margin.
    void keep_ground(const recon::GroundFilterParams& params) {
        const recon::GroundLattice lattice = tin_ground_lattice(grid_, margin_, min_x_, min_y_, params);
        std::vector<recon::GroundSample> samples(points_.size());
        for (std::size_t i = 0; i < points_.size(); ++i) samples[i] = {points_[i].x, points_[i].y, points_[i].dz};
        const std::vector<std::uint8_t> ground = recon::find_ground(samples, lattice, params);
        std::vector<recon::GroundSample>().swap(samples);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < points_.size(); ++i) {
            if (ground[i]) points_[kept++] = points_[i];
        }
        points_.truncate(kept);
    }

    lidarscout::OverviewPoint expanded(const Held& h) const {
        lidarscout::OverviewPoint p;
        p.x = h.x, p.y = h.y, p.z = base_z_ + h.dz, p.rgb = h.rgb;
        return p;
    }

    std::vector<lidarscout::OverviewPoint> expanded() const {
        std::vector<lidarscout::OverviewPoint> out(points_.size());
        for (std::size_t i = 0; i < points_.size(); ++i) out[i] = expanded(points_[i]);
        return out;
    }

    // The face map with the texels of triangles whose longest edge exceeds the limit cleared.
    recon::FaceMap without_long_edges(const recon::Triangulation& tri, recon::FaceMap map) const {
        if (!(spec_.tin_max_edge_m > 0)) return map;
        const double limit = spec_.tin_max_edge_m / grid_.texel_m * double(recon::kGridUnitsPerTexel);
        const double limit2 = limit * limit;
        std::vector<char> killed(tri.triangles.size(), 0);
        for (std::size_t t = 0; t < tri.triangles.size(); ++t) {
            const auto& v = tri.triangles[t];
            for (int k = 0; k < 3; ++k) {
                const auto &a = tri.vertices[v[k]], &b = tri.vertices[v[(k + 1) % 3]];
                if ((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) > limit2) killed[t] = 1;
            }
        }
        for (auto& f : map.face) {
            if (f >= 0 && killed[static_cast<std::size_t>(f)]) f = -1;
        }
        return map;
    }

    std::vector<std::uint8_t> colours(const recon::PatchPoints& patch, const recon::Triangulation& tri,
                                      const recon::FaceMap& map) const {
        recon::Image rgb(patch.size(), 3);
        recon::fill_linear(rgb, tri, map, recon::colour_values(patch));
        const recon::Image block = recon::crop_centre(rgb, grid_.block);
        return rgba_planes(block.texels(), [&](std::size_t i) {
            return std::array<float, 3>{block.values[i], block.values[block.texels() + i],
                                        block.values[2 * block.texels() + i]};
        });
    }

    GridderSpec spec_;
    DemGrid grid_;
    int margin_;
    double min_x_, min_y_, base_z_ = 0;
    ChunkedVector<Held> points_;
};

// The highest point of each texel of the block and its margin; the block's texels without one
// take the TIN of those points (the Delaunay triangulation of all of them), within its edge limit:
// a TinGridder of them asked for the holes only, which walks to each hole's triangle.
class HighestTinGridder final : public BlockGridder {
public:
    HighestTinGridder(const GridderSpec& spec, const DemGrid& grid, lidarscout::CellKey block)
        : tin_(spec, grid, block), grid_(grid), side_(grid.block + 2 * tin_.margin()),
          first_col_(long(block.ix) * grid.block - tin_.margin()),
          first_row_(long(block.iy) * grid.block - tin_.margin()), highest_(static_cast<std::size_t>(side_) * side_) {}

    void add(const dataset::MetricPoint& p, const recon::TexelLocation* own) override {
        const auto at = recon::locate_texel(grid_.block_spec(), grid_.origin_x, grid_.origin_y, p.x, p.y);
        if (at) add_located(p, own, *at);
    }

    // `at`: the texel in the whole grid's lattice (as every block sees it, so neighbours pick alike).
    void add_located(const dataset::MetricPoint& p, const recon::TexelLocation*,
                     const recon::TexelLocation& at) override {
        const long col = long(at.cell.ix) * grid_.block + at.col - first_col_;
        const long row = long(at.cell.iy) * grid_.block + at.row - first_row_;
        if (col < 0 || row < 0 || col >= side_ || row >= side_) return;
        Highest& h = highest_[static_cast<std::size_t>(row) * side_ + col];
        if (h.set && !(p.z > h.z)) return;
        h = {p.x, p.y, p.z, true};
    }

    BlockImages finish() override {
        const int n = grid_.block, m = tin_.margin();
        BlockImages out;
        out.heights_m.assign(static_cast<std::size_t>(n) * n, recon::kNoValue);
        std::vector<char> holes(out.heights_m.size(), 0);
        for (int row = 0; row < n; ++row) {
            for (int col = 0; col < n; ++col) {
                const Highest& h = highest_[static_cast<std::size_t>(row + m) * side_ + col + m];
                const std::size_t i = static_cast<std::size_t>(row) * n + col;
                if (h.set) out.heights_m[i] = static_cast<float>(h.z);
                else holes[i] = 1;
            }
        }
        const bool any_hole = any_marked(holes);
        if (any_hole) {
            dataset::MetricPoint p;
            for (const Highest& h : highest_) {
                if (!h.set) continue;
                p.x = h.x, p.y = h.y, p.z = h.z;
                tin_.add(p, nullptr);
            }
        }
        std::vector<Highest>().swap(highest_);
        if (!any_hole) return out;
        const BlockImages tin = tin_.finish_at(&holes);
        for (std::size_t i = 0; i < holes.size(); ++i) {
            if (holes[i]) out.heights_m[i] = tin.heights_m[i];
        }
        return out;
    }

private:
    struct Highest {
        double x = 0, y = 0, z = 0;
        bool set = false;
    };

    TinGridder tin_;
    DemGrid grid_;
    int side_;
    long first_col_, first_row_;
    std::vector<Highest> highest_;
};

void validate(const GridderSpec& spec, const DemGrid& grid) {
    if (spec.method == GridMethod::Idw) {
        if (!(spec.idw_radius_m >= 0) || !std::isfinite(spec.idw_radius_m)) {
            throw Error::in_stage("dem", "--radius must be a positive number of metres");
        }
        if (!(spec.idw_power > 0) || !std::isfinite(spec.idw_power)) {
            throw Error::in_stage("dem", "--power must be a positive number");
        }
    }
    if (spec.method == GridMethod::Tin || spec.method == GridMethod::HighestTin) {
        if (!(spec.tin_max_edge_m >= 0) || !std::isfinite(spec.tin_max_edge_m)) {
            throw Error::in_stage("dem", "--max-edge must be 0 (no limit) or a positive number of metres");
        }
        if (grid.block + 2 * tin_margin_texels(spec, grid.texel_m) > kTinWindowTexels) {
            throw Error::in_stage("dem", "tin blocks of " + std::to_string(grid.block) +
                                             " texels leave no room for the margin (internal error)");
        }
    }
}

}  // namespace

double gridder_reach_m(const GridderSpec& spec, double texel_m) {
    switch (spec.method) {
    case GridMethod::Statistic: return 0;
    case GridMethod::Idw: return spec.idw_radius_m > 0 ? spec.idw_radius_m : texel_m * std::sqrt(2.0);
    case GridMethod::Tin:
    case GridMethod::HighestTin: return tin_margin_texels(spec, texel_m) * texel_m;
    }
    return 0;
}

int tin_margin_texels(const GridderSpec& spec, double texel_m) {
    if (spec.method != GridMethod::Tin && spec.method != GridMethod::HighestTin) return 0;
    if (!(spec.tin_max_edge_m > 0)) return kMaxTinMarginTexels;
    double reach_m = spec.tin_max_edge_m;
    if (spec.ground) {
        const recon::GroundLattice lattice = recon::ground_lattice(0, 0, kTinWindowTexels * texel_m, *spec.ground);
        reach_m = std::max(reach_m, recon::ground_filter_reach_m(*spec.ground, lattice.cell_m));
    }
    constexpr int kSpareTexels = 4;
    const double texels = std::ceil(reach_m / texel_m - 1e-9) + kSpareTexels;
    return static_cast<int>(std::min<double>(texels, kMaxTinMarginTexels));
}

int tin_block_texels(int margin) { return margin > 0 ? kTinWindowTexels - 2 * margin : kTinWindowTexels; }

recon::GroundLattice tin_ground_lattice(const DemGrid& grid, int margin, double block_min_x, double block_min_y,
                                        const recon::GroundFilterParams& params) {
    const double margin_m = margin * grid.texel_m;
    return recon::ground_lattice(block_min_x - margin_m, block_min_y - margin_m,
                                 (grid.block + 2.0 * margin) * grid.texel_m, params);
}

std::unique_ptr<BlockGridder> make_block_gridder(const GridderSpec& spec, const DemGrid& grid, CellKey block) {
    validate(spec, grid);
    switch (spec.method) {
    case GridMethod::Statistic: return std::make_unique<StatisticGridder>(spec, grid);
    case GridMethod::Idw: return std::make_unique<IdwGridder>(spec, grid, block);
    case GridMethod::Tin: return std::make_unique<TinGridder>(spec, grid, block);
    case GridMethod::HighestTin: return std::make_unique<HighestTinGridder>(spec, grid, block);
    }
    return nullptr;
}

}  // namespace lidarscout::raster
