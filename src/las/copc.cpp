// COPC info VLR and hierarchy pages (see copc.hpp), with validation of every page and entry
// against the file so that a hostile hierarchy cannot loop, over-allocate or point outside.
#include "las/copc.hpp"

#include <deque>
#include <unordered_set>

#include "core/error.hpp"
#include "io/byte_reader.hpp"
#include "io/file.hpp"

namespace lidarscout::las {
namespace {

constexpr std::uint64_t kInfoSize = 160;
constexpr std::uint64_t kEntrySize = 32;
constexpr std::int32_t kMaxLevel = 30;  // keys are int32: x, y, z < 2^level must fit

struct Entry {
    CopcNode node;
    std::uint64_t file_offset = 0;  // where the entry itself is, for error messages
};

Entry read_entry(io::ByteReader& r) {
    Entry e;
    e.file_offset = r.file_offset();
    e.node.level = r.i32("COPC key level");
    e.node.x = r.i32("COPC key x");
    e.node.y = r.i32("COPC key y");
    e.node.z = r.i32("COPC key z");
    e.node.offset = r.u64("COPC entry offset");
    e.node.byte_size = r.i32("COPC entry byte size");
    e.node.point_count = r.i32("COPC entry point count");
    return e;
}

std::string key_text(const CopcNode& n) {
    return std::to_string(n.level) + "-" + std::to_string(n.x) + "-" + std::to_string(n.y) + "-" + std::to_string(n.z);
}

// [offset, offset + size) lies inside the file (no overflow).
bool inside(std::uint64_t offset, std::uint64_t size, std::uint64_t file_size) {
    return size <= file_size && offset <= file_size - size;
}

void check_key(const io::File& file, const Entry& e) {
    const CopcNode& n = e.node;
    const bool level_ok = n.level >= 0 && n.level <= kMaxLevel;
    const std::int64_t cells = level_ok ? (std::int64_t{1} << n.level) : 0;
    auto in_range = [&](std::int32_t v) { return v >= 0 && v < cells; };
    if (!level_ok || !in_range(n.x) || !in_range(n.y) || !in_range(n.z)) {
        throw Error(file.path(), e.file_offset, "COPC hierarchy entry has an invalid key " + key_text(n));
    }
}

struct Page {
    std::uint64_t offset, size;
    std::uint64_t referenced_at;  // file offset of what pointed here (info VLR or entry)
};

void check_page(const io::File& file, const Page& p) {
    if (p.size == 0 || p.size % kEntrySize != 0) {
        throw Error(file.path(), p.referenced_at,
                    "COPC hierarchy page at " + std::to_string(p.offset) + " has size " + std::to_string(p.size) +
                        ", not a positive multiple of 32");
    }
    if (!inside(p.offset, p.size, file.size())) {
        throw Error(file.path(), p.referenced_at,
                    "COPC hierarchy page [" + std::to_string(p.offset) + ", +" + std::to_string(p.size) +
                        ") lies outside the file (" + std::to_string(file.size()) + " bytes)");
    }
}

void check_data_node(const io::File& file, const Entry& e) {
    const CopcNode& n = e.node;
    if (n.byte_size <= 0 || !inside(n.offset, static_cast<std::uint64_t>(n.byte_size), file.size())) {
        throw Error(file.path(), e.file_offset,
                    "COPC node " + key_text(n) + " data [" + std::to_string(n.offset) + ", +" +
                        std::to_string(n.byte_size) + ") is empty or lies outside the file (" +
                        std::to_string(file.size()) + " bytes)");
    }
}

}  // namespace

std::optional<CopcInfo> find_copc_info(const std::vector<Vlr>& vlrs, const std::string& file) {
    if (vlrs.empty() || !vlrs.front().is("copc", 1)) return std::nullopt;
    const Vlr& v = vlrs.front();
    if (v.data_size != kInfoSize || v.data.size() != kInfoSize) {
        throw Error(
            file, v.data_offset,
            "COPC info VLR is " + std::to_string(v.data_size) + " bytes, expected " + std::to_string(kInfoSize));
    }
    io::ByteReader r(v.data, v.data_offset, file);
    CopcInfo info;
    for (double& c : info.center) c = r.f64("COPC centre");
    info.halfsize = r.f64("COPC halfsize");
    info.spacing = r.f64("COPC spacing");
    info.root_hier_offset = r.u64("COPC root hierarchy offset");
    info.root_hier_size = r.u64("COPC root hierarchy size");
    info.gpstime_min = r.f64("COPC gpstime minimum");
    info.gpstime_max = r.f64("COPC gpstime maximum");
    return info;
}

CopcHierarchy read_copc_hierarchy(const io::File& file, const CopcInfo& info) {
    CopcHierarchy h;
    const std::uint64_t max_entries = file.size() / kEntrySize;
    std::uint64_t entries = 0;
    std::unordered_set<std::uint64_t> visited;
    // The root page is referenced by the info VLR's root_hier_offset field: 40 bytes into its
    // payload, which follows the 375-byte header and the 54-byte VLR header (COPC requires
    // the info VLR to come first).
    constexpr std::uint64_t kRootFieldOffset = 375 + 54 + 40;
    std::deque<Page> queue{{info.root_hier_offset, info.root_hier_size, kRootFieldOffset}};
    while (!queue.empty()) {
        const Page page = queue.front();
        queue.pop_front();
        check_page(file, page);
        if (!visited.insert(page.offset).second) {
            throw Error(file.path(), page.referenced_at,
                        "COPC hierarchy page at " + std::to_string(page.offset) + " is referenced twice (a cycle)");
        }
        entries += page.size / kEntrySize;
        if (entries > max_entries) {
            throw Error(file.path(), page.offset,
                        "COPC hierarchy pages hold more than " + std::to_string(max_entries) +
                            " entries, more than a file of this size can");
        }
        ++h.pages;
        const auto bytes = file.read_vector(page.offset, page.size, "COPC hierarchy page");
        io::ByteReader r(bytes, page.offset, file.path());
        while (r.remaining() > 0) {
            const Entry e = read_entry(r);
            check_key(file, e);
            const std::int32_t count = e.node.point_count;
            if (count > 0) {
                check_data_node(file, e);
                h.nodes.push_back(e.node);
                h.total_points += static_cast<std::uint64_t>(count);
            } else if (count == -1) {
                if (e.node.byte_size <= 0) {
                    throw Error(file.path(), e.file_offset,
                                "COPC node " + key_text(e.node) + " points to a child page of size " +
                                    std::to_string(e.node.byte_size));
                }
                queue.push_back({e.node.offset, static_cast<std::uint64_t>(e.node.byte_size), e.file_offset});
            } else if (count < -1) {
                throw Error(file.path(), e.file_offset,
                            "COPC node " + key_text(e.node) + " has point count " + std::to_string(count));
            }
        }
    }
    return h;
}

}  // namespace lidarscout::las
