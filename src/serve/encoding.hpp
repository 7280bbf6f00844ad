// The API's binary forms, little-endian, read by web/data.js:
//
// A block of points (the chunk points of one 640 m patch-grid cell, or a square of a tile's
// full-resolution points): a 24-byte header (int32 ix, iy; uint32 n; float32 z_min, z_max; uint32
// reserved 0) then n uint32 positions (x: 11 bits, y: 11 bits, z: 10 bits; x, y on a 2048-step
// lattice over the block, 0.31 m for 640 m, 6 cm for 128 m; z over the block's [z_min, z_max]: 4
// bytes per point), n RGB triples, n classes and n uint16 intensities, all as arrays (which
// compress better than interleaved records).
//
// A level of detail of a tile: a 32-byte header (float32 origin x, y, z: metres from the grid
// origin; float32 block_m, spacing_m; uint32 level, blocks, reserved 0) then its blocks, (ix, iy)
// the block's column and row from the origin. Level L of 4 holds the points whose index i in the
// tile has i % 4^(3-L) == 0 and none of a lower level: each level four times the points of all
// before it, together every point once.
//
// A heightmap patch: int32 ix, iy; uint16 size, flags (bit 0: colours follow); float32 origin x,
// y (metres from the grid origin), texel_m, z_min, z_max; then size x size uint16 heights (row 0
// south, 65535 = no data, else z_min + h / 65534 * (z_max - z_min)) and, with colours, size x size
// RGB triples.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/patch_grid.hpp"
#include "render/point_batch.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::serve {

inline constexpr int kXyBits = 11, kZBits = 10;
inline constexpr std::uint16_t kNoHeight = 65535;

inline constexpr int kLevels = 4;
inline constexpr double kLodBlockM = 128.0;

// Appends a block of `points` (dx, dy within [0, size] of the block's corner; dz the height) as
// block (ix, iy).
void append_block(std::string& out, std::int32_t ix, std::int32_t iy, std::span<const render::PointAttr> points,
                  double size);

// The levels of detail of a tile's points (viewer::tile_point_set: origin the tile's min corner),
// origin relative to (origin_x, origin_y); with the number of points of each.
struct EncodedLevel {
    std::string body;
    std::uint64_t points = 0;
};
std::vector<EncodedLevel> encode_levels(const viewer::PointSet& set, double origin_x, double origin_y);

// A position decoded as the page decodes it (for tests): metres from the cell's corner and z.
struct DecodedPosition {
    double dx = 0, dy = 0, z = 0;
};
DecodedPosition decode_position(std::uint32_t packed, double patch_size, float z_min, float z_max);

// Appends `heightmap` with its origin relative to (origin_x, origin_y).
void append_heightmap(std::string& out, const viewer::PatchHeightmap& heightmap, double origin_x, double origin_y);

}  // namespace lidarscout::serve
