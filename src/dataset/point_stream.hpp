// Every point of a dataset's tile in the dataset's frame (metres), batch by batch, in file
// order: the records are decoded (LAZ chunks in parallel, point_reader.hpp), placed in metres
// and given an 8-bit colour (one depth decision per tile). What `eval`, `train-data` and the
// DEMs made from every point read.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "core/patch_grid.hpp"
#include "dataset/point_reader.hpp"
#include "las/point_fields.hpp"

namespace lidarscout {
class ThreadPool;
}

namespace lidarscout::dataset {

struct Dataset;

// Called with the index (in the file) of the batch's first point and the batch's points.
using MetricBatchFn = std::function<void(std::uint64_t first_point, std::span<const MetricPoint> points)>;

// Called with the tile (its index in the dataset), the index in the file of the batch's first
// point and the batch's points.
using TileMetricBatchFn =
    std::function<void(std::uint32_t tile, std::uint64_t first_point, std::span<const MetricPoint> points)>;
// Called once a tile's last batch has been through fn (also for a tile without points).
using TileDoneFn = std::function<void(std::uint32_t tile)>;
// Called (on the caller's thread, before the batch that lacks them) for what could not be read
// and was left out: a LAZ chunk, or a whole tile that cannot be opened (first_point 0, points
// all of the tile's), with the file, byte offset and cause.
using SkippedFn = std::function<void(std::uint32_t tile, const SkippedChunk& skipped)>;

// Streams the tiles `tiles` of `dataset` one after the other, in that order. The next batch,
// of this tile or the next, is decoded and placed on `pool` while fn (or tile_done) runs, so
// the pool's threads never wait for the caller at a tile's end; fn and tile_done may use
// `pool`. Memory is two batches of about `batch_points` points (at least one LAZ chunk).
// Throws lidarscout::Error when a tile cannot be decoded, unless `skipped` is given: then a
// chunk (or tile) that cannot be is left out, reported to it, and the stream goes on.
void for_each_metric_batch(const Dataset& dataset, std::span<const std::uint32_t> tiles, ThreadPool& pool,
                           const TileMetricBatchFn& fn, const TileDoneFn& tile_done,
                           std::uint32_t fields = las::fields::kAll, std::uint64_t batch_points = 1u << 20,
                           const SkippedFn& skipped = nullptr);

// Streams tile `tile` of `dataset`; `fields` is a las::fields mask (fields not asked for read
// as zero), as the function above does for one tile.
// Throws lidarscout::Error when the tile cannot be decoded.
void for_each_metric_batch(const Dataset& dataset, std::uint32_t tile, ThreadPool& pool, const MetricBatchFn& fn,
                           std::uint32_t fields = las::fields::kAll);

// Whether a tile stores 16-bit colour, judged from its chunk points (colour_is_16bit).
bool tile_colour_is_16bit(const Dataset& dataset, std::uint32_t tile);

}  // namespace lidarscout::dataset
