// Writing one LAS or LAZ file from raw point records: the header, the VLRs (plus the LASzip
// VLR for LAZ), the records streamed in (for LAZ cut into chunks encoded in parallel, then
// the chunk table), the EVLRs, and the final header. The file appears under its name only
// when finish() completes (io::AtomicOutputFile). Used by convert_tile and the generators.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "io/output_file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/vlr.hpp"

namespace lidarscout {
class ThreadPool;
}

namespace lidarscout::laz {

struct LasWriterOptions {
    bool compress = true;               // write LAZ (else LAS)
    std::uint32_t chunk_size = 50'000;  // points per LAZ chunk
    bool variable_chunks = false;       // store per-chunk point counts (as COPC does)
};

struct LasWriterResult {
    std::uint64_t points = 0;
    std::uint64_t chunks = 0;  // 0 for LAS
    std::uint64_t bytes_written = 0;
};

class LasWriter {
public:
    // Starts `path` (refused when it names the file `protect`, an input). `header` gives the
    // version, header_size (the standard size plus `header_trailing` user bytes), point
    // format, record length, scale/offset and the descriptive fields; the writer sets the
    // structural ones (compression bit, VLR/EVLR counts and offsets, point count). A LASzip
    // VLR in `vlrs` is dropped: the writer adds its own for LAZ. Throws lidarscout::Error.
    LasWriter(const std::string& path, las::Header header, std::vector<las::Vlr> vlrs, const LasWriterOptions& options,
              ThreadPool& pool, std::vector<std::uint8_t> header_trailing = {}, const std::string& protect = {});
    ~LasWriter();  // without finish() the partial output is removed
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;

    // Appends whole records (record_length bytes each) in file order.
    void add(std::span<const std::uint8_t> records);
    std::uint64_t points() const noexcept { return points_; }

    // The header written at finish(): callers may update descriptive fields (bounds, points
    // by return, GPS time range) until then.
    las::Header& header() noexcept { return header_; }

    // Writes the remaining chunks, the chunk table, `evlrs` (payloads in Vlr::data) and the
    // final header (point count = records added), then renames the file into place.
    LasWriterResult finish(const std::vector<las::Vlr>& evlrs = {});

private:
    class Chunks;  // the LAZ chunk cutter and encoder

    las::Header header_;
    std::vector<std::uint8_t> header_trailing_;
    std::vector<las::Vlr> vlrs_;
    LasWriterOptions options_;
    io::AtomicOutputFile out_;
    las::LaszipVlr laz_;
    std::unique_ptr<Chunks> chunks_;  // set for LAZ
    std::uint64_t points_ = 0;
    std::uint64_t table_pointer_at_ = 0;
    bool finished_ = false;
};

}  // namespace lidarscout::laz
