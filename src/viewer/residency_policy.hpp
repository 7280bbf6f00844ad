// The residency's decisions (residency.hpp), with no thread, lock or decoding, so that they can be
// tested on their own: the table of tiles held (full or at their coarse levels) and of tiles that
// failed; what a tile would improve per byte decoded (its screen-space error: the spacing shown
// now, heightmap texels or coarse levels, in pixels at its nearest distance, times its screen
// coverage) and what a held one is worth per byte freed (out of view: least recently seen first);
// the next tile to load, whole or in part, and what drops for it (only when the load is worth more
// than what it displaces, by a hysteresis factor, and all it holds fits the budget); the partial
// tiles the camera left. The tiles in view come from a tile index, so a look costs what is in view.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "dataset/tile_index.hpp"
#include "render/camera.hpp"
#include "viewer/decode_memory.hpp"
#include "viewer/point_lod.hpp"

namespace lidarscout::viewer {

struct ResidencyOptions;

class ResidencyPolicy {
public:
    static constexpr std::uint64_t kPiecePoints = 1u << 18;  // points decoded (whole chunks) before they are shown

    enum class Level { Coarse, Full };
    struct Entry {
        Level level = Level::Full;
        LodBlocks blocks;
        std::uint64_t bytes = 0, coarse_bytes = 0;
        std::uint64_t last_seen = 0;  // the look that last saw it in view
        bool partial = false;         // full resolution for the pieces that fitted only
        std::uint64_t loaded_at = 0;  // the camera version it was loaded for
        double coverage = 0;          // a partial one: the share of its view its pieces covered when loaded
    };
    using Entries = std::map<std::uint32_t, Entry>;

    // A tile to load and what to drop for it.
    struct Choice {
        std::uint32_t tile = 0;
        std::vector<std::uint32_t> victims;
        std::uint64_t cap = 0;    // bytes of points it may take: less than the whole tile for a partial load
        std::uint64_t extra = 0;  // its blocks' and patch details' bookkeeping
        DecodePlan plan;          // its pieces and what decoding them holds besides
    };
    // Tile -> its screen coverage (screen_fraction), for the tiles in view.
    struct Fractions : std::unordered_map<std::uint32_t, double> {
        double of(std::uint32_t tile) const;  // 0 when out of view
    };

    ResidencyPolicy(const dataset::Dataset& dataset, const PatchGrid& grid, const ResidencyOptions& options);

    // Tiles covering this share of the image or less are not wanted (ResidencyOptions::min_screen_fraction).
    void set_min_screen_fraction(double fraction) { min_screen_fraction_ = fraction; }
    // The camera of the looks that follow and its version (partial tiles remember the one they were loaded for).
    void set_camera(const render::Camera& camera, std::uint64_t version);
    const render::Camera& camera() const { return camera_; }

    // The tiles in view at `camera` and their coverage, found through the tile index.
    Fractions screen_fractions(const render::Camera& camera) const;
    // Tiles loaded in part for an earlier camera whose pieces cover less than half the share of the
    // view they covered when loaded: they drop to their coarse levels and are decoded again for this view.
    std::vector<std::uint32_t> stale_partials(const Fractions& fractions) const;
    // The next tile to load for a look that found `fractions` in view, with `held` bytes held in all
    // of a `budget`; the held tiles in view are marked seen. nullopt: nothing worth loading fits.
    std::optional<Choice> choose(const Fractions& fractions, std::uint64_t held, std::uint64_t budget);
    // What to release, cheapest first, so that `held` falls within `budget` (nothing is worth keeping
    // over the budget); empty when it is within.
    std::vector<std::uint32_t> over_budget(std::uint64_t held, std::uint64_t budget) const;
    // The share of what the camera sees of a tile (`fraction`) that the blocks of `entry` cover.
    double coverage(const Entry& entry, double fraction) const;
    // What loading `tile` adds besides its points: its blocks' headers, the patch details of the cells it covers.
    std::uint64_t bookkeeping_bytes(std::uint32_t tile) const;

    Entries& entries() { return entries_; }
    const Entries& entries() const { return entries_; }
    std::set<std::uint32_t>& failed() { return failed_; }
    std::uint64_t tick() const { return tick_; }  // looks so far
    std::size_t wanted() const { return wanted_; }            // tiles in view at the last choose
    std::size_t wanted_full() const { return wanted_full_; }  // of those, held whole at full resolution
    // Whether the tile in view of most screen coverage at the last choose (the one nearest the camera, about)
    // is held whole at full resolution; false when none was in view.
    bool largest_full() const { return largest_full_; }
    std::uint64_t index_visits() const { return index_.visits(); }

private:
    struct Step {
        double value = 0;  // worth per byte freed
        std::uint32_t tile = 0;
        std::uint64_t freed = 0;
    };
    struct Room {
        std::vector<std::uint32_t> victims;
        std::uint64_t total = 0;  // bytes held once they are released
    };
    std::vector<Step> release_steps() const;
    // What to release, cheapest first, so that `incoming` bytes fit with `total` held, each worth
    // less than `gain` (per byte); nullopt when that cannot be done.
    std::optional<Room> victims(std::uint64_t incoming, double gain, std::uint64_t total, std::uint64_t budget,
                                const std::vector<Step>& steps) const;
    std::optional<Choice> partial_choice(std::uint32_t tile, double gain, std::uint64_t total, std::uint64_t budget,
                                         const std::vector<Step>& steps) const;
    double value_per_byte(std::uint32_t tile, const Entry& entry) const;
    // What decoding `tile` would improve per byte, given its screen coverage `fraction`.
    double gain_per_byte(std::uint32_t tile, double fraction) const;
    // The decode plan for the whole of `tile` whose transient bytes fit in `room` (decode_memory.hpp).
    std::optional<DecodePlan> plan_for(std::uint32_t tile, std::uint64_t room) const;

    const dataset::Dataset& dataset_;
    const lidarscout::PatchGrid& grid_;
    unsigned decode_threads_;
    int patch_texels_;
    double block_m_, coarse_spacing_m_, hysteresis_, min_screen_fraction_;
    std::vector<double> spacing_;  // per tile: its points' mean spacing (metres)
    dataset::TileIndex index_;     // the tiles in view without a look at every tile
    render::Camera camera_;
    std::uint64_t camera_version_ = 0, tick_ = 0;
    Entries entries_;
    std::set<std::uint32_t> failed_;
    std::size_t wanted_ = 0, wanted_full_ = 0;
    bool largest_full_ = false;
};

}  // namespace lidarscout::viewer
