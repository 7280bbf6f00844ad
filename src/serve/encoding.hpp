// The API's binary forms, little-endian, read by web/data.js:
//
// A block of points (the chunk points of one 640 m patch-grid cell, or a square of a tile's
// full-resolution points): a 28-byte header (int32 ix, iy; uint32 n; float32 z_min, z_max; uint8
// attributes (bits: 1 RGB, 2 class, 4 intensity, 8 RGB 5-6-5), xy_bits, z_bits, 0; uint32 bytes of
// positions), the positions, then the attributes asked for as arrays: n RGB triples, n uint16
// RGB 5-6-5, n classes, n uint16 intensities. Positions: x, y on a lattice of 2^xy_bits steps over
// the block, z on one of 2^z_bits steps over [z_min, z_max] (chunk points: 11 and 10 bits, 0.31 m
// for 640 m; a level of detail: steps of an eighth of its point spacing, at most 11 and 16 bits);
// the points sorted by the Morton code of (x, y), each written as two LEB128 varints: the code's
// increase over the previous point's, and the zigzag of z's change. Neighbours follow one another,
// so both are small: about 2 bytes a point, gzip'd.
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

inline constexpr int kXyBits = 11, kZBits = 16, kChunkZBits = 10;
inline constexpr double kStepsPerSpacing = 8;  // lattice steps per point spacing in a level of detail
inline constexpr std::uint16_t kNoHeight = 65535;

inline constexpr int kLevels = 4;
inline constexpr double kLodBlockM = 128.0;

// Attributes a block carries besides positions.
enum Attributes : std::uint32_t { kRgb = 1, kClass = 2, kIntensity = 4, kRgb565 = 8, kAllAttributes = 7 };
// "rgb,rgb565,class,intensity" (any of them, comma-separated; empty = none); throws lidarscout::Error.
std::uint32_t parse_attributes(const std::string& text);

// Appends a block of `points` (dx, dy within [0, size] of the block's corner; dz the height) as
// block (ix, iy) with `attributes`, on a lattice of steps at most `step` metres (0: the finest, 11
// bits for x and y, 10 for z).
void append_block(std::string& out, std::int32_t ix, std::int32_t iy, std::span<const render::PointAttr> points,
                  double size, std::uint32_t attributes, double step = 0);

// A block read back (what web/data.js does; for tests): points in the block's order, positions on
// the lattice (dx, dy from the block's corner, dz the height), attributes left 0 when absent.
struct DecodedBlock {
    std::int32_t ix = 0, iy = 0;
    std::vector<render::PointAttr> points;
};
// Decodes the block at `offset` of `body` and moves offset past it; throws lidarscout::Error when
// the bytes run out.
DecodedBlock decode_block(const std::string& body, std::size_t& offset, double size);

// The levels of detail of a tile's points (viewer::tile_point_set: origin the tile's min corner),
// origin relative to (origin_x, origin_y); with the number of points of each.
struct EncodedLevel {
    std::string body;
    std::uint64_t points = 0;
};
std::vector<EncodedLevel> encode_levels(const viewer::PointSet& set, double origin_x, double origin_y,
                                        std::uint32_t attributes);

// `heightmap` with texels `step` times as large (step divides its size): each the mean of the
// defined texels it covers when at least half are, else undefined (as render's level of detail
// draws a block cut by the edge of the data).
viewer::PatchHeightmap coarsened(const viewer::PatchHeightmap& heightmap, int step);

// Appends `heightmap` with its origin relative to (origin_x, origin_y).
void append_heightmap(std::string& out, const viewer::PatchHeightmap& heightmap, double origin_x, double origin_y);

}  // namespace lidarscout::serve
