// Reading and decoding LAZ decode units, serially or in parallel, with file/chunk context
// added to every error.
#include "laz/laz.hpp"

#include <mutex>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "io/file.hpp"
#include "laz/chunk_decoder.hpp"

namespace lidarscout::laz {

std::vector<Chunk> decode_units(const las::Header& header, const las::LaszipVlr& laz, const ChunkTable& table,
                                std::uint64_t file_size) {
    if (laz.compressor != 1) return table.chunks();
    if (header.point_count == 0) return {};
    const std::uint64_t begin = header.offset_to_point_data;
    std::uint64_t end = file_size;
    if (header.number_of_evlrs > 0 && header.evlr_offset > begin) end = std::min(end, header.evlr_offset);
    return {Chunk{0, header.point_count, begin, end - begin}};
}

namespace {

// Runs `decode` (reading and decoding unit `index`), its errors named by the unit and `path`.
template <class Decode>
void in_unit(const std::string& path, const Chunk& c, std::size_t index, Decode&& decode) {
    try {
        decode();
    } catch (const Error& e) {
        const std::string where = "chunk " + std::to_string(index) + " (points " + std::to_string(c.first_point) +
                                  ".." + std::to_string(c.first_point + c.point_count) + "): ";
        if (!e.file().empty()) throw Error(e.file(), e.offset(), where + e.cause());
        throw Error(path, c.byte_offset + e.offset().value_or(0), where + e.cause());
    }
}

}  // namespace

void decode_unit(const io::File& file, const LazLayout& layout, std::size_t index, std::span<std::uint8_t> out,
                 std::uint32_t fields, std::vector<std::uint8_t>& scratch) {
    const Chunk& c = layout.units.at(index);
    scratch.resize(c.byte_size);
    in_unit(file.path(), c, index, [&] {
        file.read_exact(c.byte_offset, scratch, "LAZ chunk");
        decode_chunk(layout.laz, {scratch, c.point_count, out, fields});
    });
}

void decode_unit_bytes(const std::string& path, const LazLayout& layout, std::size_t index,
                       std::span<const std::uint8_t> bytes, std::span<std::uint8_t> out, std::uint32_t fields) {
    const Chunk& c = layout.units.at(index);
    in_unit(path, c, index, [&] {
        if (bytes.size() != c.byte_size) {
            throw Error(path, c.byte_offset, "LAZ chunk: " + std::to_string(bytes.size()) + " bytes read of " +
                                                 std::to_string(c.byte_size));
        }
        decode_chunk(layout.laz, {bytes, c.point_count, out, fields});
    });
}

void decode_units_parallel(const io::File& file, const LazLayout& layout, std::size_t first, std::size_t last,
                           std::span<std::uint8_t> out, std::uint32_t fields, ThreadPool& pool) {
    const std::size_t record = layout.header.record_length;
    const std::uint64_t base = layout.units.at(first).first_point;
    std::uint64_t total = 0;
    for (std::size_t i = first; i < last; ++i) total += layout.units[i].point_count;
    if (out.size() != total * record) {
        throw Error(file.path(), std::nullopt, "decode buffer has the wrong size (internal error)");
    }
    // Read buffers shared by the tasks of this call, one per task running at a time: a fresh
    // buffer per chunk costs page faults worth ~3% of an XYZ-only decode. Not thread_local: its
    // first use registers a destructor through __cxa_thread_atexit, which waits for the dynamic
    // loader's lock, held for ~0.7 s while LibTorch is being loaded.
    std::mutex spare_mutex;
    std::vector<std::vector<std::uint8_t>> spare;
    pool.for_each(last - first, [&](std::size_t k) {
        std::vector<std::uint8_t> scratch;
        {
            std::lock_guard lock(spare_mutex);
            if (!spare.empty()) scratch = std::move(spare.back()), spare.pop_back();
        }
        const Chunk& c = layout.units[first + k];
        decode_unit(file, layout, first + k, out.subspan((c.first_point - base) * record, c.point_count * record),
                    fields, scratch);
        std::lock_guard lock(spare_mutex);
        spare.push_back(std::move(scratch));
    });
}

}  // namespace lidarscout::laz
