// Converting a tile to a new LAS or LAZ file: LAS->LAZ, LAZ->LAS, LAZ->LAZ, optionally to
// another point format, keeping header fields, VLRs and EVLRs. The output appears under its
// name only when complete (io::AtomicOutputFile); the input is never written. Values the target
// format cannot hold are counted and refused (or, with force, written clamped with a warning).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lidarscout {
class ThreadPool;
}

namespace lidarscout::pipelines {

struct ConvertOptions {
    bool compress = true;                     // write LAZ (else LAS)
    std::optional<std::uint8_t> point_format;  // convert records to this format (0-10)
    std::uint32_t chunk_size = 50'000;        // points per LAZ chunk
    bool variable_chunks = false;             // store per-chunk point counts (as COPC does)
    // Values the target format cannot hold (las::FormatLosses) are written clamped or dropped
    // with a warning; without force the conversion is refused (nothing written) naming them.
    bool force = false;
};

struct ConvertResult {
    std::uint64_t points = 0;
    std::uint64_t bytes_written = 0;
    std::uint64_t chunks = 0;
    std::vector<std::string> notes;  // what was dropped or changed (e.g. COPC records)
    std::vector<std::string> warnings;  // values the format cannot hold, written anyway (force)
};

// Whether a point-cloud output is LAZ (.laz) or LAS (.las), by its extension; throws lidarscout::Error
// naming the path for another.
bool wants_laz(const std::string& path);

using ConvertProgressFn = std::function<void(std::uint64_t points_done)>;

ConvertResult convert_tile(const std::string& in_path, const std::string& out_path, const ConvertOptions& options,
                           ThreadPool& pool, const ConvertProgressFn& progress = {});

}  // namespace lidarscout::pipelines
