// Chunk table encoding (see chunk_table_writer.hpp).
#include "laz/chunk_table_writer.hpp"

#include <limits>
#include <string>

#include "core/error.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_compressor.hpp"

namespace lidarscout::laz {
namespace {

// Must agree with read_chunk_table: 32-bit entries in two contexts.
constexpr std::uint32_t kTableVersion = 0;
constexpr std::uint32_t kEntryBits = 32;
constexpr std::uint32_t kEntryContexts = 2;
constexpr std::uint32_t kPointCountContext = 0;
constexpr std::uint32_t kByteCountContext = 1;

void append_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint32_t entry_value(std::uint64_t v, const char* what, std::size_t index) {
    if (v > std::numeric_limits<std::uint32_t>::max()) {
        throw Error("LAZ chunk table: chunk " + std::to_string(index) + " has " + std::to_string(v) + " " + what +
                    ", more than a table entry holds");
    }
    return static_cast<std::uint32_t>(v);
}

}  // namespace

std::vector<std::uint8_t> encode_chunk_table(const std::vector<Chunk>& chunks, bool variable_chunks) {
    if (chunks.size() > std::numeric_limits<std::uint32_t>::max()) throw Error("LAZ chunk table: too many chunks");
    std::vector<std::uint8_t> out;
    append_u32(out, kTableVersion);
    append_u32(out, static_cast<std::uint32_t>(chunks.size()));
    if (chunks.empty()) return out;  // LASzip writes no coded part at all then

    ArithmeticEncoder enc;
    IntegerCompressor coder(kEntryBits, kEntryContexts);
    enc.start(out);
    std::uint32_t previous_points = 0;
    std::uint32_t previous_bytes = 0;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        if (variable_chunks) {
            const std::uint32_t points = entry_value(chunks[i].point_count, "points", i);
            coder.compress(enc, static_cast<std::int32_t>(previous_points), static_cast<std::int32_t>(points),
                           kPointCountContext);
            previous_points = points;
        }
        const std::uint32_t bytes = entry_value(chunks[i].byte_size, "bytes", i);
        coder.compress(enc, static_cast<std::int32_t>(previous_bytes), static_cast<std::int32_t>(bytes),
                       kByteCountContext);
        previous_bytes = bytes;
    }
    enc.done();
    return out;
}

}  // namespace lidarscout::laz
