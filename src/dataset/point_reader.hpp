// Streaming all point records of a tile (LAS or LAZ) in file order, batch by batch: LAZ
// batches are several chunks decoded in parallel, LAS batches are plain reads. Memory stays
// bounded by the batch size, whatever the file size.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "laz/chunk_decoder.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::io {
class File;
}

namespace lidarscout::dataset {

struct Tile;

// Called with the index of the batch's first point and its records (record_length each).
using RecordBatchFn = std::function<void(std::uint64_t first_point, std::span<const std::uint8_t> records)>;

// Reads every record of `tile`; `fields` is a laz::fields mask (LAS files always give all).
// Batches hold about `batch_points` points (at least one whole LAZ chunk). With `read_ahead`
// the next LAZ batch is decoded (on `pool`) while fn runs on this one, so fn must not use
// `pool`; memory is then two batches.
void for_each_record_batch(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                           std::uint32_t fields = laz::fields::kAll, std::uint64_t batch_points = 1u << 20,
                           bool read_ahead = false);

}  // namespace lidarscout::dataset
