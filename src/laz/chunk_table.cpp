// Locating, decoding and validating the LAZ chunk table (see chunk_table.hpp for the layout
// and the rules). The coded entries are read in a window that grows only as decoding needs
// it, so a garbage chunk count can neither allocate nor read much before it is caught.
#include "laz/laz.hpp"

#include <algorithm>
#include <optional>
#include <span>
#include <string>

#include "core/error.hpp"
#include "io/byte_reader.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz {
namespace {

constexpr std::uint64_t kPositionSize = 8;     // the int64 before the first chunk
constexpr std::uint64_t kTableHeaderSize = 8;  // u32 version, u32 chunk count
constexpr std::uint32_t kTableVersion = 0;
// Entries are coded as 32-bit integers in two contexts, each relative to the previous entry.
constexpr std::uint32_t kEntryBits = 32;
constexpr std::uint32_t kPointCountContext = 0;
constexpr std::uint32_t kByteCountContext = 1;
// The first read window: room for this many entries at most kMaxEntryBytes each (two
// integers of at most ~7 bytes each, with margin), plus a base. Larger tables (COPC files
// can have 10^5 chunks) take a few doubling rounds, each decoding from the start again.
constexpr std::uint64_t kMaxEntryBytes = 24;
constexpr std::uint64_t kBaseWindow = 4096;
constexpr std::uint64_t kEntriesInFirstWindow = 4096;
// The decoder looks 4 bytes ahead; a table whose writer left out the final zero bytes may
// make it read that far past the data, with the same result as if the zeros were there.
constexpr std::size_t kOverrunSlack = 4;

// Where the table is and which bytes it may use.
struct Location {
    std::uint64_t chunks_start = 0;  // first chunk: right after the position int64
    std::uint64_t table_offset = 0;
    bool from_file_end = false;
    std::uint64_t bytes_end = 0;     // the coded entries end at or before this offset
};

// One decoded entry, before the point counts are fitted to the header.
struct Entry {
    std::uint32_t points = 0;  // only for variable-size chunks
    std::uint32_t bytes = 0;
};

class TableReader {
public:
    TableReader(const io::File& file, const las::Header& header, const las::LaszipVlr& laz)
        : file_(file), header_(header), laz_(laz), variable_(has_variable_chunks(laz)) {}

    ChunkTable read() {
        const auto where = locate();
        if (!where) return {};
        loc_ = *where;
        const std::uint32_t count = read_count();
        ChunkTable table(fit_to_header(read_entries(count)));
        table.table_offset = loc_.table_offset;
        table.offset_from_file_end = loc_.from_file_end;
        return table;
    }

private:
    [[noreturn]] void fail(std::uint64_t offset, const std::string& cause) const {
        throw Error(file_.path(), offset, "chunk table: " + cause);
    }

    std::int64_t read_i64(std::uint64_t offset, const char* what) const {
        std::uint8_t raw[8];
        file_.read_exact(offset, raw, what);
        return io::load_le<std::int64_t>(raw);
    }

    // nullopt: an empty file without even the table position (possible only with 0 points).
    std::optional<Location> locate() const {
        Location loc;
        const std::uint64_t position_at = header_.offset_to_point_data;
        if (file_.size() < position_at + kPositionSize) {
            if (header_.point_count == 0) return std::nullopt;
            fail(position_at, "the file ends before the 8-byte chunk table position");
        }
        loc.chunks_start = position_at + kPositionSize;
        std::int64_t position = read_i64(position_at, "chunk table position");
        std::uint64_t position_field = position_at;
        loc.bytes_end = file_.size();
        if (position == -1) {  // written by a streaming writer: the position is at the end
            if (file_.size() < loc.chunks_start + kPositionSize) {
                fail(position_at, "position is -1 (at the end of the file) but the file is too short");
            }
            position_field = file_.size() - kPositionSize;
            position = read_i64(position_field, "chunk table position");
            loc.from_file_end = true;
            loc.bytes_end = position_field;
        }
        if (position == static_cast<std::int64_t>(position_at)) {
            fail(position_field, "missing: its position points at itself (the writer was interrupted before "
                                 "writing the table)");
        }
        if (position < static_cast<std::int64_t>(loc.chunks_start) ||
            static_cast<std::uint64_t>(position) + kTableHeaderSize > loc.bytes_end) {
            fail(position_field, "position " + std::to_string(position) + " lies outside " +
                                     std::to_string(loc.chunks_start) + " .. " +
                                     std::to_string(loc.bytes_end - std::min(loc.bytes_end, kTableHeaderSize)) +
                                     " (after the first chunk, before the end of the file)");
        }
        loc.table_offset = static_cast<std::uint64_t>(position);
        // EVLRs (LAS 1.4) may follow the table; the entries cannot run into them.
        if (header_.number_of_evlrs > 0 && header_.evlr_offset >= loc.table_offset + kTableHeaderSize &&
            header_.evlr_offset < loc.bytes_end) {
            loc.bytes_end = header_.evlr_offset;
        }
        return loc;
    }

    std::uint32_t read_count() const {
        std::uint8_t raw[kTableHeaderSize];
        file_.read_exact(loc_.table_offset, raw, "chunk table header");
        const auto version = io::load_le<std::uint32_t>(raw);
        const auto count = io::load_le<std::uint32_t>(raw + 4);
        if (version != kTableVersion) fail(loc_.table_offset, "unknown version " + std::to_string(version));
        const std::uint64_t chunk_bytes = loc_.table_offset - loc_.chunks_start;
        if (count > chunk_bytes) {
            fail(loc_.table_offset + 4, "announces " + std::to_string(count) + " chunks but only " +
                                            std::to_string(chunk_bytes) + " bytes of chunk data precede it");
        }
        return count;
    }

    // Reads a window of coded bytes, growing it until the entries fit (or the table's bytes
    // are exhausted).
    std::vector<Entry> read_entries(std::uint32_t count) const {
        const std::uint64_t first = loc_.table_offset + kTableHeaderSize;
        const std::uint64_t available = loc_.bytes_end - first;
        std::uint64_t window =
            kBaseWindow + kMaxEntryBytes * std::min<std::uint64_t>(count, kEntriesInFirstWindow);
        for (;;) {
            window = std::min(window, available);
            const auto coded = file_.read_vector(first, static_cast<std::size_t>(window), "chunk table");
            if (auto entries = decode_entries(coded, count, window == available)) return std::move(*entries);
            window *= 2;
        }
    }

    // nullopt: the decoder ran past `coded` while the file holds more table bytes.
    std::optional<std::vector<Entry>> decode_entries(std::span<const std::uint8_t> coded, std::uint32_t count,
                                                     bool all_bytes) const {
        std::vector<Entry> entries;
        entries.reserve(std::min<std::uint64_t>(count, kEntriesInFirstWindow));
        ArithmeticDecoder dec(coded);
        // One coder per thread, back to its start state for each table: a country's 152,100 tables had each
        // built its models anew (an eighth of the CPU while its tiles were placed from an overview sidecar).
        thread_local IntegerDecompressor ic(kEntryBits, 2);
        ic.reset();
        Entry previous;
        std::uint64_t offset = loc_.chunks_start;
        for (std::uint32_t i = 0; i < count; ++i) {
            const Entry e = decode_entry(dec, ic, previous, i);
            if (dec.overrun() > 0 && !all_bytes) return std::nullopt;
            if (dec.overrun() > kOverrunSlack) {
                fail(loc_.table_offset, "truncated: entry " + std::to_string(i) + " of " + std::to_string(count) +
                                            " runs past the end of the table's bytes at " +
                                            std::to_string(loc_.bytes_end));
            }
            check_entry(e, i, offset);
            offset += e.bytes;
            entries.push_back(e);
            previous = e;
        }
        return entries;
    }

    // The next entry, each number coded relative to the previous entry's.
    Entry decode_entry(ArithmeticDecoder& dec, IntegerDecompressor& ic, const Entry& previous,
                       std::uint32_t index) const {
        auto next = [&](std::uint32_t prediction, std::uint32_t context) {
            return static_cast<std::uint32_t>(ic.decompress(dec, static_cast<std::int32_t>(prediction), context));
        };
        try {
            Entry e;
            if (variable_) e.points = next(previous.points, kPointCountContext);
            e.bytes = next(previous.bytes, kByteCountContext);
            return e;
        } catch (const Error& decoding) {  // the decoder knows no file
            fail(loc_.table_offset, "entry " + std::to_string(index) + " is corrupt: " + decoding.cause());
        }
    }

    void check_entry(const Entry& e, std::uint32_t index, std::uint64_t offset) const {
        auto fail_chunk = [&](const std::string& what) {
            fail(loc_.table_offset, "chunk " + std::to_string(index) + " at byte " + std::to_string(offset) + what);
        };
        if (e.bytes == 0) fail_chunk(" has a size of 0 bytes");
        if (offset + e.bytes > loc_.table_offset) {
            fail_chunk(" with " + std::to_string(e.bytes) + " bytes runs past the table at " +
                       std::to_string(loc_.table_offset));
        }
        if (variable_ && e.points == 0) fail_chunk(" holds no points");
    }

    // Point counts per chunk: from the entries (variable) or the chunk size (fixed), cut at
    // the header's point count (see chunk_table.hpp).
    std::vector<Chunk> fit_to_header(const std::vector<Entry>& entries) const {
        const std::uint64_t total = header_.point_count;
        std::vector<Chunk> chunks;
        std::uint64_t first_point = 0;
        std::uint64_t offset = loc_.chunks_start;
        for (const Entry& e : entries) {
            if (first_point >= total) break;  // LASzip never reads past the header's count
            const std::uint64_t stored = variable_ ? e.points : laz_.chunk_size;
            const std::uint64_t points = std::min(stored, total - first_point);
            chunks.push_back({first_point, points, offset, e.bytes});
            first_point += points;
            offset += e.bytes;
        }
        if (first_point < total) {
            fail(loc_.table_offset, "its " + std::to_string(entries.size()) + " chunks hold " +
                                        std::to_string(first_point) + " points but the header announces " +
                                        std::to_string(total) + shortfall_hint());
        }
        return chunks;
    }

    std::string shortfall_hint() const {
        if (variable_) return "";
        return " (chunks of " + std::to_string(laz_.chunk_size) + " points; the chunks after the last listed one "
               "cannot be located without decoding)";
    }

    const io::File& file_;
    const las::Header& header_;
    const las::LaszipVlr& laz_;
    const bool variable_;
    Location loc_;
};

}  // namespace

ChunkTable::ChunkTable(const std::vector<Chunk>& chunks) {
    if (chunks.empty()) return;
    offsets_.reserve(chunks.size() + 1);
    std::uint64_t next_point = 0;
    for (const Chunk& c : chunks) {
        if (c.first_point != next_point || (!offsets_.empty() && c.byte_offset != offsets_.back())) {
            throw Error("chunk table: chunks that are not back to back (internal error)");
        }
        if (!offsets_.empty()) offsets_.pop_back();
        offsets_.push_back(c.byte_offset);
        offsets_.push_back(c.byte_offset + c.byte_size);
        next_point += c.point_count;
    }
    total_points_ = next_point;
    regular_points_ = chunks.front().point_count;
    const bool regular = regular_points_ > 0 && chunks.back().point_count <= regular_points_ &&
                         std::all_of(chunks.begin(), chunks.end() - 1,
                                     [&](const Chunk& c) { return c.point_count == regular_points_; });
    if (regular) return;
    regular_points_ = 0;
    first_points_.reserve(chunks.size() + 1);
    for (const Chunk& c : chunks) first_points_.push_back(c.first_point);
    first_points_.push_back(total_points_);
}

Chunk ChunkTable::operator[](std::size_t i) const {
    Chunk c;
    c.byte_offset = offsets_[i];
    c.byte_size = offsets_[i + 1] - offsets_[i];
    if (first_points_.empty()) {
        c.first_point = i * regular_points_;
        c.point_count = std::min(regular_points_, total_points_ - c.first_point);
    } else {
        c.first_point = first_points_[i];
        c.point_count = first_points_[i + 1] - first_points_[i];
    }
    return c;
}

std::vector<Chunk> ChunkTable::chunks() const { return {begin(), end()}; }

std::size_t ChunkTable::heap_bytes() const {
    return (offsets_.capacity() + first_points_.capacity()) * sizeof(std::uint64_t);
}

bool has_variable_chunks(const las::LaszipVlr& laz) { return laz.variable_chunks(); }

ChunkTable read_chunk_table(const io::File& file, const las::Header& header, const las::LaszipVlr& laz) {
    if (!laz.chunked()) return {};
    return TableReader(file, header, laz).read();
}

}  // namespace lidarscout::laz
