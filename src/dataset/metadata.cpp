// Counting the bytes of a dataset's metadata, shared parts once.
#include "dataset/metadata.hpp"

#include <string>
#include <unordered_set>
#include <vector>

#include "dataset/dataset.hpp"

namespace lidarscout::dataset {
namespace {

// Heap bytes of a string: none while it fits its inline buffer.
std::uint64_t heap(const std::string& s) {
    const auto* p = reinterpret_cast<const char*>(&s);
    const bool inline_buffer = s.data() >= p && s.data() < p + sizeof(s);
    return inline_buffer ? 0 : s.capacity() + 1;
}

template <typename T>
std::uint64_t buffer(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

std::uint64_t heap(const Diagnostics& d) {
    std::uint64_t n = d.size() * sizeof(Diagnostic);  // (the list does not tell its capacity)
    for (const auto& x : d) n += heap(x.file) + heap(x.message);
    return n;
}

std::uint64_t heap(const std::vector<las::Vlr>& vlrs) {
    std::uint64_t n = buffer(vlrs);
    for (const auto& v : vlrs) n += heap(v.user_id) + heap(v.description) + buffer(v.data);
    return n;
}

std::uint64_t heap(const las::Crs& c) {
    return heap(c.source) + heap(c.name) + heap(c.horizontal_unit_name) + heap(c.vertical_unit_name) + heap(c.wkt) +
           heap(c.warnings);
}

std::uint64_t heap(const TileRecords& r) {
    return heap(r.vlrs) + heap(r.evlrs) + heap(r.crs) + (r.laz ? buffer(r.laz->items) : 0);
}

// What tiles hold once, whoever holds them.
class SharedParts {
public:
    std::uint64_t bytes = 0;

    void add(const TileFile& f) {
        if (!seen_.insert(&f).second) return;
        bytes += sizeof(TileFile) + heap(f.path) + heap(f.warnings) + (f.chunks ? f.chunks->heap_bytes() : 0);
        if (f.records && seen_.insert(f.records.get()).second) bytes += sizeof(TileRecords) + heap(*f.records);
    }

private:
    std::unordered_set<const void*> seen_;
};

}  // namespace

std::uint64_t metadata_bytes(const Dataset& ds) {
    std::uint64_t n = sizeof(Dataset) + ds.tiles.capacity() * sizeof(DatasetTile);
    SharedParts shared;
    for (const auto& t : ds.tiles) {
        n += heap(t.tile.header.system_identifier) + heap(t.tile.header.generating_software);
        if (t.tile.file) shared.add(*t.tile.file);
    }
    n += shared.bytes;
    n += buffer(ds.skipped);
    for (const auto& s : ds.skipped) n += heap(s.path) + heap(s.error);
    return n + heap(ds.warnings) + heap(ds.frame.crs);
}

}  // namespace lidarscout::dataset
