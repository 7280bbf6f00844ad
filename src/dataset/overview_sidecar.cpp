// Reading an overview sidecar: its table (parsed with bounds checks), its points (the whole file read
// at once, its chunks decoded in parallel a group at a time), a tile from its entry, and the check of a tile
// read in full.
#include "dataset/overview_sidecar.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <utility>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "core/thread_priority.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/point_reader.hpp"
#include "io/byte_reader.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/vlr.hpp"
#include "net/remote_file.hpp"

namespace lidarscout::dataset {
namespace {

constexpr std::uint32_t kVersion = 1;
constexpr char kMagic[4] = {'L', 'S', 'O', 'V'};
constexpr const char* kLocalTag = "mtime ";

void put(std::vector<std::uint8_t>& out, const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out.insert(out.end(), b, b + n);
}
template <typename T>
void put_value(std::vector<std::uint8_t>& out, T v) {
    put(out, &v, sizeof v);
}
template <typename Size>
void put_bytes(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes) {
    if (bytes.size() > std::numeric_limits<Size>::max()) throw Error("overview table: a field too long");
    put_value(out, static_cast<Size>(bytes.size()));
    put(out, bytes.data(), bytes.size());
}
std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}
std::string text_of(std::span<const std::uint8_t> b) { return {reinterpret_cast<const char*>(b.data()), b.size()}; }

// Where a head's VLR block lies: [header size, offset to point data).
std::pair<std::size_t, std::size_t> vlr_block(const std::vector<std::uint8_t>& head) {
    if (head.size() < 100) throw Error("overview table: a tile's head shorter than a LAS header");
    std::uint16_t header_size = 0;
    std::uint32_t point_data = 0;
    std::memcpy(&header_size, head.data() + 94, 2);
    std::memcpy(&point_data, head.data() + 96, 4);
    const std::size_t end = std::min<std::size_t>(std::max<std::size_t>(point_data, header_size), head.size());
    return {std::min<std::size_t>(header_size, head.size()), end};
}

void put_entry(std::vector<std::uint8_t>& out, const OverviewEntry& e, std::uint32_t block) {
    const auto [first, last] = vlr_block(e.head);
    const std::span<const std::uint8_t> head(e.head);
    put_bytes<std::uint16_t>(out, bytes_of(e.id));
    put_value(out, e.made_from.size);
    put_bytes<std::uint16_t>(out, bytes_of(e.made_from.tag));
    put_value(out, e.first_point);
    put_value(out, e.points);
    for (const auto d : e.delta) put_value(out, d);
    put_bytes<std::uint16_t>(out, head.first(first));
    put_value(out, block);
    put_bytes<std::uint16_t>(out, head.subspan(last));
    put_bytes<std::uint32_t>(out, e.tail);
}

OverviewEntry parse_entry(io::ByteReader& r, const std::vector<std::vector<std::uint8_t>>& blocks) {
    OverviewEntry e;
    e.id = text_of(r.bytes(r.u16("id length"), "id"));
    e.made_from.size = r.u64("file size");
    e.made_from.tag = text_of(r.bytes(r.u16("validator length"), "validator"));
    e.first_point = r.u64("first point");
    e.points = r.u32("points");
    for (auto& d : e.delta) d = r.i64("delta");
    const auto header = r.bytes(r.u16("header length"), "header");
    const std::uint32_t block = r.u32("VLR block");
    if (block >= blocks.size()) r.fail("VLR block index", 0);
    const auto after = r.bytes(r.u16("after length"), "bytes after the VLRs");
    e.head.reserve(header.size() + blocks[block].size() + after.size());
    e.head.assign(header.begin(), header.end());
    e.head.insert(e.head.end(), blocks[block].begin(), blocks[block].end());
    e.head.insert(e.head.end(), after.begin(), after.end());
    const auto tail = r.bytes(r.u32("tail length"), "tail");
    e.tail.assign(tail.begin(), tail.end());
    return e;
}

// The whole file at `path` in memory (one read after its opening), as an io::File.
io::File whole_file(const std::string& path) {
    const io::File file = io::File::open(path);
    return io::File::in_memory(file.path(), file.size(), file.read_vector(0, file.size(), "overview sidecar"), {});
}

// The table EVLR's entries (made on `pool` where given); throws Error when the file has none.
std::vector<OverviewEntry> table_of(const io::File& file, const las::Header& header, ThreadPool* pool = nullptr) {
    for (const auto& v : las::read_evlrs(file, header)) {
        if (!v.is(kOverviewUser, kOverviewTableRecord)) continue;
        if (v.data_loaded) return parse_overview_table(v.data, file.path(), pool);
        // (a sidecar read whole is parsed where its table lies: a country's is 66 MB, copied first it was as
        // many fresh pages)
        if (const auto held = file.held(v.data_offset, v.data_size); !held.empty()) {
            return parse_overview_table(held, file.path(), pool);
        }
        return parse_overview_table(las::vlr_payload(file, v), file.path(), pool);
    }
    throw Error(file.path(), std::nullopt, "not an overview sidecar (no lidarscout tile table EVLR)");
}

// Where a held entry's points lie in the sidecar and how they go back to its tile's (what decoding its records
// needs of the table).
struct HeldPoints {
    std::uint64_t first_point = 0;
    std::uint32_t points = 0;
    std::array<std::int64_t, 3> delta{};
};

// Every record of the sidecar's tile `k` back to the tile's own (its X/Y/Z less the delta), appended.
void take_records(std::span<const std::uint8_t> in, std::size_t in_length, const HeldPoints& e, std::uint32_t k,
                  std::vector<std::uint8_t>& out, const std::string& file) {
    const std::size_t length = in_length - kOverviewTileField;
    for (std::size_t p = 0; p < e.points; ++p) {
        const std::uint8_t* r = in.data() + p * in_length;
        std::uint32_t tile = 0;
        std::memcpy(&tile, r + length, 4);
        if (tile != k) throw Error(file, std::nullopt, "overview point of tile " + std::to_string(tile) +
                                                           " where the table puts tile " + std::to_string(k));
        const std::size_t at = out.size();
        out.insert(out.end(), r, r + length);
        for (int a = 0; a < 3; ++a) {
            std::int32_t v = 0;
            std::memcpy(&v, out.data() + at + 4 * a, 4);
            v = static_cast<std::int32_t>(v - e.delta[a]);
            std::memcpy(out.data() + at + 4 * a, &v, 4);
        }
    }
}

// Whether the held entries' points lie in the order of the entries, none overlapping another (as the writer lays
// them out): then they can be taken while the sidecar is decoded a piece at a time.
bool entries_in_point_order(std::span<const HeldPoints> entries) {
    std::uint64_t end = 0;
    for (const auto& e : entries) {
        if (e.points == 0) continue;
        if (e.first_point < end) return false;
        end = e.first_point + e.points;
    }
    return true;
}

// The sidecar's records, decoded a group of units (LAZ chunks) at a time on `pool` into one buffer that keeps only
// what is still to be taken: a country's sidecar (5.8 M records, 200 MB decoded) is never held whole beside the
// blocks it is taken into, nor are its pages cleared twice. `whole`: every unit in one group (entries out of order).
class DecodedWindow {
public:
    DecodedWindow(const io::File& file, const Tile& tile, ThreadPool& pool, bool whole)
        : file_(file), units_(tile), pool_(pool), length_(tile.header.record_length),
          group_(whole ? units_.size() : std::max<std::size_t>(1, 2 * pool.size())) {}

    // The records of points [from, from + count) (decoded by now); those before `from` may be let go.
    std::span<const std::uint8_t> records(std::uint64_t from, std::uint64_t count) {
        while (from + count > end_) {
            if (next_ == units_.size()) throw Error(file_.path(), std::nullopt, "overview points past its chunks");
            decode_next(from);
        }
        return std::span(bytes_).subspan((from - first_) * length_, count * length_);
    }

private:
    void decode_next(std::uint64_t keep_from) {
        if (keep_from > first_) {  // (what lies before is taken: the rest moved to the front)
            const std::size_t drop = static_cast<std::size_t>(std::min(keep_from, end_) - first_) * length_;
            bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(drop));
            first_ += drop / length_;
        }
        const std::size_t last = std::min(units_.size(), next_ + group_);
        std::uint64_t points = 0;
        for (std::size_t u = next_; u < last; ++u) points += units_.point_count(u);
        const std::size_t at = bytes_.size();
        bytes_.resize(at + static_cast<std::size_t>(points) * length_);
        units_.decode(file_, next_, last, std::span(bytes_).subspan(at), las::fields::kAll, pool_);
        end_ = first_ + bytes_.size() / length_;
        next_ = last;
    }

    const io::File& file_;
    const DecodeUnits units_;
    ThreadPool& pool_;
    const std::size_t length_, group_;
    std::vector<std::uint8_t> bytes_;  // the records of points [first_, end_)
    std::uint64_t first_ = 0, end_ = 0;
    std::size_t next_ = 0;  // the next unit to decode
};

// What filling a sidecar's blocks needs: per entry its points and its block (OverviewSidecar::block_of).
struct Filling {
    std::vector<HeldPoints> entries;
    std::vector<std::shared_ptr<std::vector<std::uint8_t>>> blocks;
    std::vector<std::uint32_t> block_of;
};

// Each entry's place in the blocks (an entry in one block, the next block begun once one holds
// kOverviewBlockBytes), each block reserved to its final size; what filling them needs. Throws Error when the
// records are too short or an entry's points lie past the sidecar's.
Filling lay_out_blocks(const io::File& file, const Tile& tile, OverviewSidecar& s) {
    const std::size_t in_length = tile.header.record_length;
    if (in_length < kOverviewTileField + 20) throw Error(file.path(), 105, "records too short for an overview");
    s.record_length = static_cast<std::uint16_t>(in_length - kOverviewTileField);
    Filling f;
    f.entries.reserve(s.entries.size());
    std::vector<std::size_t> sizes;
    for (std::uint32_t k = 0; k < s.entries.size(); ++k) {
        const auto& e = s.entries[k];
        if (sizes.empty() || sizes.back() >= kOverviewBlockBytes) sizes.push_back(0);
        s.block_of.push_back(static_cast<std::uint32_t>(sizes.size() - 1));
        s.record_starts.push_back(sizes.back());
        f.entries.push_back({e.first_point, e.points, e.delta});
        if (e.points == 0) continue;
        if (e.first_point > tile.header.point_count || e.points > tile.header.point_count - e.first_point) {
            throw Error(file.path(), std::nullopt, "overview tile " + std::to_string(k) + " past the points");
        }
        sizes.back() += std::size_t{e.points} * s.record_length;
    }
    for (const std::size_t size : sizes) {
        s.blocks.push_back(std::make_shared<std::vector<std::uint8_t>>());
        s.blocks.back()->reserve(size);
    }
    f.blocks = s.blocks;
    f.block_of = s.block_of;
    return f;
}

// The held entries' records decoded (on `pool`) into their blocks, each taken back to its tile's own; false when
// `stop` said so before the end. Throws Error.
bool fill_blocks(const io::File& file, const Tile& tile, const Filling& f, ThreadPool& pool,
                 const std::function<bool()>& stop) {
    const std::size_t in_length = tile.header.record_length;
    std::optional<DecodedWindow> window;
    std::vector<std::uint8_t> all;  // (an uncompressed sidecar's records, read at once)
    if (tile.compressed()) {
        window.emplace(file, tile, pool, !entries_in_point_order(f.entries));
    } else {
        all.resize(tile.header.point_count * in_length);
        file.read_exact(tile.header.offset_to_point_data, all, "overview points");
    }
    for (std::uint32_t k = 0; k < f.entries.size(); ++k) {
        const auto& e = f.entries[k];
        if (e.points == 0) continue;
        if (stop && stop()) return false;
        const auto records = window ? window->records(e.first_point, e.points)
                                    : std::span<const std::uint8_t>(all).subspan(e.first_point * in_length);
        take_records(records, in_length, e, k, *f.blocks[f.block_of[k]], file.path());
    }
    return true;
}

}  // namespace

std::string overview_path_for(const std::string& catalog) {
    std::filesystem::path p(catalog);
    return p.replace_extension(".overview.laz").string();
}

FileValidator file_validator(const io::File& file) {
    FileValidator v{file.size(), {}};
    if (file.remote()) {
        v.tag = file.remote()->validator();
    } else if (struct stat st {}; file.fd() >= 0 && ::fstat(file.fd(), &st) == 0) {
        v.tag = kLocalTag + std::to_string(st.st_mtim.tv_sec * 1'000'000'000LL + st.st_mtim.tv_nsec);
    }
    return v;
}

bool validator_matches(const FileValidator& made_from, const FileValidator& now) {
    if (made_from.size != now.size) return false;
    const auto local = [](const std::string& tag) { return tag.rfind(kLocalTag, 0) == 0; };
    if (made_from.tag.empty() || now.tag.empty() || local(made_from.tag) != local(now.tag)) return true;
    return made_from.tag == now.tag;
}

std::vector<std::uint8_t> serialize_overview_table(std::span<const OverviewEntry> entries) {
    std::map<std::vector<std::uint8_t>, std::uint32_t> index;
    std::vector<const std::vector<std::uint8_t>*> blocks;
    std::vector<std::uint32_t> block_of;
    for (const auto& e : entries) {
        const auto [first, last] = vlr_block(e.head);
        std::vector<std::uint8_t> block(e.head.begin() + first, e.head.begin() + last);
        const auto [it, added] = index.try_emplace(std::move(block), static_cast<std::uint32_t>(index.size()));
        if (added) blocks.push_back(&it->first);
        block_of.push_back(it->second);
    }
    std::vector<std::uint8_t> out(kMagic, kMagic + 4);
    put_value(out, kVersion);
    put_value(out, static_cast<std::uint32_t>(blocks.size()));
    put_value(out, static_cast<std::uint32_t>(entries.size()));
    for (const auto* b : blocks) put_bytes<std::uint32_t>(out, *b);
    for (std::size_t k = 0; k < entries.size(); ++k) put_entry(out, entries[k], block_of[k]);
    return out;
}

namespace {

// Moves `r` past one entry (put_entry's layout) without making it.
void skip_entry(io::ByteReader& r) {
    r.skip(r.u16("id length"), "id");
    r.skip(8, "file size");
    r.skip(r.u16("validator length"), "validator");
    r.skip(8 + 4 + 3 * 8, "points and deltas");
    r.skip(r.u16("header length"), "header");
    r.skip(4, "VLR block");
    r.skip(r.u16("after length"), "bytes after the VLRs");
    r.skip(r.u32("tail length"), "tail");
}

}  // namespace

std::vector<OverviewEntry> parse_overview_table(std::span<const std::uint8_t> payload, const std::string& file,
                                                ThreadPool* pool) {
    io::ByteReader r(payload, 0, file);
    const auto magic = r.bytes(4, "table signature");
    if (!std::equal(magic.begin(), magic.end(), kMagic)) throw Error(file, std::nullopt, "not an overview table");
    if (const auto version = r.u32("version"); version != kVersion) {
        throw Error(file, std::nullopt, "overview table version " + std::to_string(version) + " (1 is read)");
    }
    const std::uint32_t block_count = r.u32("VLR blocks"), tiles = r.u32("tiles");
    std::vector<std::vector<std::uint8_t>> blocks;
    for (std::uint32_t b = 0; b < block_count; ++b) {
        const auto bytes = r.bytes(r.u32("VLR block length"), "VLR block");
        blocks.emplace_back(bytes.begin(), bytes.end());
    }
    if (!pool) {  // (no room made for `tiles` entries: the count is the file's word until its entries are there)
        std::vector<OverviewEntry> entries;
        for (std::uint32_t k = 0; k < tiles; ++k) entries.push_back(parse_entry(r, blocks));
        return entries;
    }
    // Where each run of kRun entries starts (one pass over their lengths, which ends at the payload's end: a count
    // the entries do not fill is an Error before any room is made), then the runs made on `pool`: a country's table
    // (152,100 entries, 64 MB) had been made on one thread while the open and the decoding waited for it.
    constexpr std::uint32_t kRun = 1024;
    std::vector<std::size_t> starts;
    for (std::uint32_t k = 0; k < tiles; ++k) {
        if (k % kRun == 0) starts.push_back(r.position());
        skip_entry(r);
    }
    std::vector<OverviewEntry> entries(tiles);
    pool->for_each_block(tiles, kRun, [&](std::size_t begin, std::size_t end) {
        io::ByteReader at(payload, 0, file);
        at.skip(starts[begin / kRun]);
        for (std::size_t k = begin; k < end; ++k) entries[k] = parse_entry(at, blocks);
    });
    return entries;
}

namespace {

// The sidecar in `file` (all its bytes in memory): its table, its points decoded.
OverviewSidecar sidecar_of(const io::File& file, ThreadPool& pool) {
    const Tile tile = read_tile(file);
    OverviewSidecar s;
    s.entries = table_of(file, tile.header, &pool);
    fill_blocks(file, tile, lay_out_blocks(file, tile, s), pool, {});
    return s;
}

constexpr int kPrefetchNice = 10;  // a prefetch's threads yield to the catalog's parse and the frames

// Where a prefetch waits between its download and its decoding (decode_overview_prefetch).
struct Gate {
    std::mutex mutex;
    std::condition_variable opened;
    bool open = false;
    void let_through() {
        {
            std::lock_guard lock(mutex);
            open = true;
        }
        opened.notify_all();
    }
    void wait() {
        std::unique_lock lock(mutex);
        opened.wait(lock, [&] { return open; });
    }
};

// What stale_tile_check and a failed decoding (OverviewDecoding::fail) have to say, for take_stale_tile_warnings.
struct StaleWarnings {
    std::mutex mutex;
    std::set<std::string> named;
    Diagnostics warnings;
};
StaleWarnings& stale_warnings() {
    static StaleWarnings w;
    return w;
}

// The one prefetch kept (prefetch_overview_sidecar), and the threads of those before, still decoding.
struct Prefetch {
    std::mutex mutex;
    std::string path;
    std::future<OverviewSidecar> sidecar;  // its table read, its points being decoded
    std::shared_ptr<Gate> gate;
    std::atomic<bool> exiting{false};  // (before the threads: it outlives their joining)
    std::vector<std::future<void>> threads;
    ~Prefetch() {  // (at exit: the futures wait for their threads, which must not wait at the gate nor decode on)
        exiting = true;
        if (gate) gate->let_through();
    }
};
Prefetch& prefetch() {
    stale_warnings();  // (made first, so that it outlives the prefetch threads: a failed decoding warns there)
    static Prefetch p;
    return p;
}

// A prefetch's work on its thread: the file read whole, then (once let through) its table into `sidecar`, then
// its points decoded into the blocks while the sidecar's taker places its tiles; stops once nobody holds them.
void run_prefetch(const std::string& path, Gate& gate, std::promise<OverviewSidecar>& sidecar) {
    lower_thread_priority(kPrefetchNice);  // (the pool below inherits it)
    std::optional<io::File> file;
    Tile tile;
    OverviewSidecar s;
    Filling filling;
    std::optional<ThreadPool> pool;  // (its threads at this one's priority: the table's and the decoding's)
    try {
        file.emplace(whole_file(path));
        gate.wait();
        tile = read_tile(*file);
        pool.emplace(ThreadPool::shared_size());
        s.entries = table_of(*file, tile.header, &*pool);
        filling = lay_out_blocks(*file, tile, s);
    } catch (...) {
        return sidecar.set_exception(std::current_exception());
    }
    auto decoding = std::make_shared<OverviewDecoding>(file->path());
    s.decoding = decoding;
    sidecar.set_value(std::move(s));
    const auto unused = [&] { return decoding.use_count() == 1 || prefetch().exiting.load(); };
    try {
        fill_blocks(*file, tile, filling, *pool, unused) ? decoding->finish() : decoding->abandon();
    } catch (const Error& e) {
        decoding->fail(e.file() == file->path() ? e.cause() : e.what());  // (the warning names the sidecar)
    } catch (const std::exception& e) {  // (out of memory: its readers must not wait for ever)
        decoding->fail(e.what());
    }
}

}  // namespace

void OverviewDecoding::finish() { end(kDone); }

void OverviewDecoding::abandon() { end(kFailed); }

void OverviewDecoding::fail(const std::string& cause) {
    {
        StaleWarnings& w = stale_warnings();
        std::lock_guard lock(w.mutex);
        w.warnings.add({DiagnosticLevel::warning, file_, std::nullopt,
                        io::display_path(file_) + ": overview sidecar's points not used (" + cause +
                            "): its tiles' chunk points are read from the tiles"});
    }
    end(kFailed);
}

void OverviewDecoding::end(int state) {
    {
        std::lock_guard lock(mutex_);
        state_.store(state, std::memory_order_release);
    }
    ended_.notify_all();
}

bool OverviewDecoding::wait() const {
    if (!ended()) {
        std::unique_lock lock(mutex_);
        ended_.wait(lock, [&] { return ended(); });
    }
    return !failed();
}

OverviewSidecar read_overview_sidecar(const std::string& path) {
    std::future<OverviewSidecar> started;
    {
        std::lock_guard lock(prefetch().mutex);
        if (prefetch().path == path) {
            started = std::move(prefetch().sidecar);
            prefetch().gate->let_through();
            prefetch().path.clear();
        }
    }
    if (!started.valid()) return sidecar_of(whole_file(path), ThreadPool::shared());
    return started.get();
}

void prefetch_overview_sidecar(const std::string& path) {
    if (!overview_sidecars_in_use()) return;
    forget_overview_prefetch();
    Prefetch& p = prefetch();
    std::lock_guard lock(p.mutex);
    std::erase_if(p.threads, [](const std::future<void>& t) {
        return t.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    });
    auto promise = std::make_shared<std::promise<OverviewSidecar>>();
    p.path = path;
    p.gate = std::make_shared<Gate>();
    p.sidecar = promise->get_future();
    p.threads.push_back(std::async(std::launch::async, [path, gate = p.gate, promise] {
        run_prefetch(path, *gate, *promise);
    }));
}

void decode_overview_prefetch() {
    std::lock_guard lock(prefetch().mutex);
    if (prefetch().gate) prefetch().gate->let_through();
}

void forget_overview_prefetch() {
    std::future<OverviewSidecar> dropped;
    {
        std::lock_guard lock(prefetch().mutex);
        dropped = std::move(prefetch().sidecar);
        if (prefetch().gate) prefetch().gate->let_through();  // (a thread waiting there ends)
        prefetch().path.clear();
    }
    if (dropped.valid()) dropped.wait();  // (its thread ends; the sidecar goes with the future)
}

Tile tile_from_overview(const OverviewSidecar& sidecar, std::size_t entry, const std::string& path,
                        SharedRecords* shared_records) {
    const OverviewEntry& e = sidecar.entries.at(entry);
    auto overview = std::make_shared<TileOverview>();
    overview->made_from = e.made_from;
    overview->decoding = sidecar.decoding;
    std::uint16_t record_length = 0;  // the tile's, from its header's bytes
    if (e.head.size() >= 107) std::memcpy(&record_length, e.head.data() + 105, 2);
    if (e.points > 0 && record_length == sidecar.record_length) {
        overview->records = sidecar.blocks.at(sidecar.block_of.at(entry));
        overview->first = sidecar.record_starts.at(entry) / sidecar.record_length;
        overview->count = e.points;
    }
    TileOptions options;
    options.shared_records = shared_records;
    options.overview = std::move(overview);
    return read_tile(io::File::in_memory(path, e.made_from.size, e.head, e.tail), options);
}

namespace {
std::vector<std::uint8_t>* block_of(const Tile& tile) {
    const TileOverview* o = tile.file ? tile.file->overview.get() : nullptr;
    return o ? o->records.get() : nullptr;
}
}  // namespace

OverviewRelease::OverviewRelease(std::span<const DatasetTile> tiles, std::span<const std::uint32_t> taking) {
    for (const std::uint32_t id : taking) {
        if (auto* b = block_of(tiles[id].tile)) ++left_[b];
    }
}

void OverviewRelease::taken(const Tile& tile) {
    const auto it = left_.find(block_of(tile));
    if (it == left_.end() || --it->second > 0) return;
    released_ += it->first->capacity();
    std::vector<std::uint8_t>().swap(*it->first);
    left_.erase(it);
    // (the blocks were allocated by the sidecar's decoding thread: freed, they stay in its arena, which nothing
    // else allocates from, while the reader's grid grows; a country's view peaked 180 MB over its budget's share
    // until the heap was trimmed at the end)
    if (released_ >= kTrimEvery) trim_heap(), released_ = 0;
}

bool overview_holds(const Tile& tile, std::uint64_t chunk_points) {
    const TileOverview* o = tile.file ? tile.file->overview.get() : nullptr;
    if (!o || !o->records || o->count == 0 || o->count != chunk_points) return false;
    return !o->decoding || !o->decoding->failed();
}

std::span<const std::uint8_t> overview_records(const Tile& tile, std::uint64_t chunk_points) {
    const TileOverview* o = tile.file ? tile.file->overview.get() : nullptr;
    if (!o || !o->records || o->count == 0 || o->count != chunk_points) return {};
    if (o->decoding && !o->decoding->wait()) return {};
    const std::size_t length = tile.header.record_length;
    if (o->records->size() < (o->first + o->count) * length) return {};  // (released)
    return std::span(*o->records).subspan(o->first * length, o->count * length);
}

std::optional<Tile> stale_tile_check(const Tile& tile, const io::File& file) {
    const TileOverview* o = tile.file ? tile.file->overview.get() : nullptr;
    if (!o) return std::nullopt;
    const FileValidator now = file_validator(file);
    if (validator_matches(o->made_from, now)) return std::nullopt;
    Tile fresh = read_tile(file);
    StaleWarnings& w = stale_warnings();
    std::lock_guard lock(w.mutex);
    if (w.named.insert(tile.path()).second) {
        w.warnings.add({DiagnosticLevel::warning, tile.path(), std::nullopt,
                        io::display_path(tile.path()) + " changed since its catalog's overview sidecar was written (" +
                            std::to_string(o->made_from.size) + " bytes then, " + std::to_string(now.size) +
                            " now): read from the file itself"});
    }
    return fresh;
}

const DatasetTile& tile_to_read(const DatasetTile& tile, const io::File& file, std::optional<DatasetTile>& fresh) {
    auto read = stale_tile_check(tile.tile, file);
    if (!read) return tile;
    fresh = tile;
    fresh->tile = std::move(*read);
    fresh->chunk_points = chunk_point_count(fresh->tile);
    return *fresh;
}

Diagnostics take_stale_tile_warnings() {
    StaleWarnings& w = stale_warnings();
    std::lock_guard lock(w.mutex);
    return std::exchange(w.warnings, {});
}

}  // namespace lidarscout::dataset
