// ResidencyPolicy: the worth of tiles on screen, the choice of the next tile to decode and of what
// drops for it, partial loads and the partial tiles the camera left.
#include "viewer/residency_policy.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "viewer/point_sets.hpp"
#include "viewer/residency.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::uint64_t kMinPartialBytes =
    4 * ResidencyPolicy::kPiecePoints * sizeof(render::PointAttr);  // worth a partial load
constexpr std::size_t kMaxTries = 64;  // candidates tried per look, best first

// Pixels by which showing `box` at spacing `shown_m` misses its own spacing `own_m`, at its
// nearest distance.
double error_px(const render::Camera& camera, const dataset::Bounds& box, double shown_m, double own_m) {
    return std::max(shown_m - own_m, 0.0) / pixel_footprint(camera, distance_to(camera, box));
}

}  // namespace

double ResidencyPolicy::Fractions::of(std::uint32_t tile) const {
    const auto it = find(tile);
    return it == end() ? 0.0 : it->second;
}

ResidencyPolicy::ResidencyPolicy(const dataset::Dataset& dataset, const lidarscout::PatchGrid& grid,
                                 const ResidencyOptions& options)
    : dataset_(dataset), grid_(grid), decode_threads_(std::max(1u, options.decode_threads)),
      patch_texels_(options.patch_texels), block_m_(options.block_m), coarse_spacing_m_(options.coarse_spacing_m),
      hysteresis_(options.hysteresis), min_screen_fraction_(options.min_screen_fraction), index_(dataset) {
    spacing_.reserve(dataset.tiles.size());
    for (const auto& t : dataset.tiles) spacing_.push_back(mean_point_spacing(t));
}

void ResidencyPolicy::set_camera(const render::Camera& camera, std::uint64_t version) {
    camera_ = camera;
    camera_version_ = version;
}

double ResidencyPolicy::gain_per_byte(std::uint32_t tile, double fraction) const {
    const auto& t = dataset_.tiles[tile];
    const double shown = entries_.contains(tile) ? coarse_spacing_m_ : grid_.patch_size() / patch_texels_;
    const double bytes = static_cast<double>(std::max<std::uint64_t>(tile_point_set_bytes(t), 1));
    return error_px(camera_, dataset_.bounds(tile), shown, spacing_[tile]) * fraction / bytes;
}

double ResidencyPolicy::value_per_byte(std::uint32_t tile, const Entry& entry) const {
    const auto& b = dataset_.bounds(tile);
    const double fraction = screen_fraction(camera_, b);
    if (fraction <= 0)
        return -1.0 / (1.0 + static_cast<double>(entry.last_seen));  // out of view: least recently seen first
    if (entry.level == Level::Full) {
        const double freed = static_cast<double>(std::max<std::uint64_t>(entry.bytes - entry.coarse_bytes, 1));
        return error_px(camera_, b, coarse_spacing_m_, spacing_[tile]) * fraction / freed;
    }
    const double texel = grid_.patch_size() / patch_texels_;
    return error_px(camera_, b, texel, coarse_spacing_m_) * fraction /
           static_cast<double>(std::max<std::uint64_t>(entry.bytes, 1));
}

std::optional<DecodePlan> ResidencyPolicy::plan_for(std::uint32_t tile, std::uint64_t room) const {
    const auto& t = dataset_.tiles[tile];
    return fitting_decode_plan(t, t.tile.header.point_count, decode_threads_, kPiecePoints, room);
}

std::uint64_t ResidencyPolicy::bookkeeping_bytes(std::uint32_t tile) const {
    const auto& b = dataset_.bounds(tile);
    const auto across = [&](double side) {
        return static_cast<std::uint64_t>(std::ceil(std::max(b.max_x - b.min_x, 0.0) / side) + 1) *
               static_cast<std::uint64_t>(std::ceil(std::max(b.max_y - b.min_y, 0.0) / side) + 1);
    };
    const auto texels = static_cast<std::uint64_t>(patch_texels_) * patch_texels_;
    // Every point's layer and the ground's (the usual classified survey; water is rarer).
    const std::uint64_t detail = texels * kDetailLayerTexelBytes * 2 + sizeof(PatchDetail);
    return across(block_m_) * sizeof(LodBlock) + across(grid_.patch_size()) * detail;
}

std::vector<ResidencyPolicy::Step> ResidencyPolicy::release_steps() const {
    // A full tile drops to its coarse levels, then to nothing; cheapest worth per byte first.
    std::vector<Step> steps;
    for (const auto& [tile, e] : entries_) {
        const double v = value_per_byte(tile, e);
        if (e.level == Level::Coarse) {
            steps.push_back({v, tile, e.bytes});
            continue;
        }
        steps.push_back({v, tile, e.bytes - e.coarse_bytes});
        const Entry coarse{Level::Coarse, {}, e.coarse_bytes, 0, e.last_seen};
        steps.push_back({std::max(v, value_per_byte(tile, coarse)), tile, e.coarse_bytes});
    }
    std::stable_sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) { return a.value < b.value; });
    return steps;
}

std::optional<ResidencyPolicy::Room> ResidencyPolicy::victims(std::uint64_t incoming, double gain, std::uint64_t total,
                                                              std::uint64_t budget,
                                                              const std::vector<Step>& steps) const {
    Room room{{}, total};
    for (const Step& s : steps) {
        if (room.total + incoming <= budget) break;
        if (s.value * hysteresis_ >= gain) return std::nullopt;
        room.victims.push_back(s.tile);
        room.total -= std::min(room.total, s.freed);
    }
    if (room.total + incoming > budget) return std::nullopt;
    return room;
}

std::vector<std::uint32_t> ResidencyPolicy::over_budget(std::uint64_t held, std::uint64_t budget) const {
    return victims(0, std::numeric_limits<double>::infinity(), held, budget, release_steps()).value_or(Room{}).victims;
}

ResidencyPolicy::Fractions ResidencyPolicy::screen_fractions(const render::Camera& camera) const {
    Fractions out;
    index_.visit([&](const dataset::Bounds& box) { return box_in_view(camera, box); },
                 [&](std::uint32_t t) {
                     const double f = screen_fraction(camera, dataset_.bounds(t));
                     if (f > 0) out.emplace(t, f);
                 });
    return out;
}

std::optional<ResidencyPolicy::Choice> ResidencyPolicy::choose(const Fractions& fractions, std::uint64_t held,
                                                               std::uint64_t budget) {
    ++tick_;
    wanted_ = wanted_full_ = 0;
    double largest = 0;
    largest_full_ = false;
    std::vector<std::pair<double, std::uint32_t>> candidates;  // (gain per byte, tile)
    for (const auto& [i, fraction] : fractions) {
        // (a tile whose header is not read yet waits: the chunk-point loader reads those in view first)
        if (fraction <= min_screen_fraction_ || failed_.contains(i) || !dataset_.is_ready(i)) continue;
        ++wanted_;
        const auto it = entries_.find(i);
        if (it != entries_.end()) it->second.last_seen = tick_;
        const bool whole = it != entries_.end() && it->second.level == Level::Full && !it->second.partial;
        if (fraction > largest) largest = fraction, largest_full_ = whole;
        if (it != entries_.end() && it->second.level == Level::Full) {
            wanted_full_ += whole;
            continue;
        }
        candidates.emplace_back(gain_per_byte(i, fraction), i);
    }
    // The best that fits: a tile larger than the budget allows must not stop the others.
    std::sort(candidates.begin(), candidates.end(), std::greater<>());
    if (candidates.size() > kMaxTries) candidates.resize(kMaxTries);
    const auto steps = release_steps();
    for (const auto& [gain, tile] : candidates) {
        const auto& t = dataset_.tiles[tile];
        const std::uint64_t bytes = tile_point_set_bytes(t), extra = bookkeeping_bytes(tile);
        const std::uint64_t least = decode_plan(t, t.tile.header.point_count, decode_threads_, 1).transient;
        auto room = victims(bytes + extra + least, gain, held, budget, steps);
        if (!room) continue;
        const auto plan = plan_for(tile, budget - room->total - bytes - extra);  // `least` fitted
        return Choice{tile, std::move(room->victims), bytes, extra, *plan};
    }
    // None fits whole: the best one in part (its pieces in view first), in the room there is.
    for (const auto& [gain, tile] : candidates) {
        auto choice = partial_choice(tile, gain, held, budget, steps);
        if (choice) return choice;
    }
    return std::nullopt;
}

std::optional<ResidencyPolicy::Choice> ResidencyPolicy::partial_choice(std::uint32_t tile, double gain,
                                                                       std::uint64_t total, std::uint64_t budget,
                                                                       const std::vector<Step>& steps) const {
    Choice c{tile, {}, 0, bookkeeping_bytes(tile), {}};
    for (const Step& s : steps) {
        if (s.value * hysteresis_ >= gain) break;
        c.victims.push_back(s.tile);
        total -= std::min(total, s.freed);
    }
    if (total + c.extra >= budget) return std::nullopt;
    const std::uint64_t room = budget - total - c.extra;
    // Its decoding takes at most a quarter of the room, else the least it can; the points the rest.
    auto plan = plan_for(tile, room / 4);
    if (!plan) plan = plan_for(tile, room);
    if (!plan) return std::nullopt;
    c.plan = *plan;
    c.cap = room - plan->transient;
    // The first piece is always decoded whole; less room than a few pieces is not worth a load.
    const auto& t = dataset_.tiles[tile];
    const std::uint64_t piece = std::min(tile_point_set_bytes(t), (plan->piece_points - 1 + largest_unit_points(t)) *
                                                                      sizeof(render::PointAttr));
    if (c.cap < std::max(piece, std::min(kMinPartialBytes, budget / 16))) return std::nullopt;
    return c;
}

double ResidencyPolicy::coverage(const Entry& entry, double fraction) const {
    double covered = 0;
    for (const auto& b : entry.blocks) covered += screen_fraction(camera_, b->bounds);
    return fraction > 0 ? std::min(covered / fraction, 1.0) : 1.0;
}

std::vector<std::uint32_t> ResidencyPolicy::stale_partials(const Fractions& fractions) const {
    std::vector<std::uint32_t> out;
    for (const auto& [tile, e] : entries_) {
        const double fraction = fractions.of(tile);
        if (!e.partial || e.level != Level::Full || e.loaded_at == camera_version_ || fraction <= 0) continue;
        if (coverage(e, fraction) < 0.5 * e.coverage) out.push_back(tile);
    }
    return out;
}

}  // namespace lidarscout::viewer
