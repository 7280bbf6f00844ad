// The heightmap of one patch as the viewer keeps and draws it: 64 x 64 heights in metres and
// an RGBA texture over a 640 m cell of the patch grid, built from the cell's chunk points by
// the linear method (recon) or from the network's output, and masked to the tiles' footprints
// so that a patch on the edge of the data does not show terrain nobody scanned.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "dataset/tile_index.hpp"
#include "core/patch_grid.hpp"
#include "recon/methods.hpp"
#include "recon/patch_space.hpp"
#include "render/heightmap_pass.hpp"

namespace lidarscout::viewer {

// What a heightmap's heights stand for: every point (the overview, and the detail of every point),
// or the bare earth of the ground (class 2) and/or water (class 9) points a filter keeps.
enum class Surface : std::uint8_t { All, Ground, Water, GroundAndWater };

// The surface `filter` asks the heightmaps for: a filter that keeps some of classes 2 and 9 and no
// other class asks for that bare earth (whatever its returns and intensities); any other for All.
Surface surface_of(const PointFilter& filter);
// "every point", "ground", "water", "ground and water".
const char* surface_name(Surface surface);

// A texel's colour alpha in a bare-earth heightmap where it still shows the overview (no
// full-resolution point read there yet): drawn tinted, never passed off as ground.
inline constexpr std::uint8_t kOverviewAlpha = 0x80;

// The colour of a texel without one (rgba8 grey, what the heightmap pass draws for an untextured patch).
inline constexpr std::uint32_t kNoColourGrey = 0xffaaaaaau;

struct PatchHeightmap {
    lidarscout::CellKey cell;
    double origin_x = 0, origin_y = 0;  // south-west corner of the patch, world metres
    double texel_m = 10;
    int size = 64;                      // texels per side
    std::vector<float> heights;         // size x size, row 0 = south; metres, NaN = no data
    std::vector<std::uint32_t> colours; // rgba8 (render/framebuffer.hpp), or empty without colour
    std::uint64_t cache_key = 0;        // render::HeightmapPatch::cache_key (given by share())
    Surface surface = Surface::All;     // what its heights stand for (texels of alpha kOverviewAlpha excepted)

    // The heightmap pass's view of this patch (spans into this object), drawn for a frame that
    // wants `wanted`: a heightmap of another surface is tinted whole (it stands in for one not
    // read yet), one of a bare-earth surface has its overview texels tinted.
    render::HeightmapPatch view(Surface wanted = Surface::All) const;
};

// The heightmap, complete, shared read-only from now on (with a cache key for the GPU).
std::shared_ptr<const PatchHeightmap> share(PatchHeightmap heightmap);

// A heightmap from a patch-sized reconstruction (recon::Reconstruction of size x size texels:
// normalised heights, colours in [0, 1] or NaN) of the window `points` of `cell`.
PatchHeightmap heightmap_from_reconstruction(lidarscout::CellKey cell, const recon::PatchPoints& points,
                                             const recon::Reconstruction& patch);

// The linear method (barycentric in the chunk points' triangles, nearest outside) on the
// window of `cell`, cropped to the patch; nullopt when the window has too few chunk points
// (options.min_points). The grid's patch size must be options.spec.patch_m().
std::optional<PatchHeightmap> linear_heightmap(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell,
                                               const recon::PatchOptions& options);

// The tiles' footprints (xy boxes, metres) a heightmap is masked to, indexed by position so that those about a
// patch are found without looking at every one (a country's 152,100 had been scanned for each heightmap built:
// a third of the builder's time while the chunk points came in). Copies share the index.
class Footprints {
public:
    Footprints() = default;
    Footprints(std::vector<dataset::Bounds> boxes);  // NOLINT: implicit, a list of boxes is footprints
    Footprints(std::initializer_list<dataset::Bounds> boxes) : Footprints(std::vector<dataset::Bounds>(boxes)) {}

    bool empty() const { return size() == 0; }
    std::size_t size() const { return shared_ ? shared_->index.size() : 0; }
    // The boxes that overlap [x0, x1] x [y0, y1] (edges touching included). Safe on several threads at once.
    std::vector<dataset::Bounds> overlapping(double x0, double y0, double x1, double y1) const;

private:
    struct Shared {
        dataset::TileIndex index;  // (it holds the boxes; counts its visits: one thread at a time)
        std::mutex mutex;
    };
    std::shared_ptr<Shared> shared_;
};

// Sets to NaN every texel whose centre lies outside all `footprints`; returns false when no texel is left.
bool mask_to_footprints(PatchHeightmap& heightmap, const Footprints& footprints);

}  // namespace lidarscout::viewer
