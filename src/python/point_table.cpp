// PointTable over an anonymous mapping reserved without swap (MAP_NORESERVE), and point_fields.
#include "python/point_table.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <utility>
#include <vector>

namespace lidarscout::python {

PointFields point_fields(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles) {
    PointFields f;
    for (const auto t : tiles) {
        const auto& format = las::point_format_info(ds.tiles[t].tile.header.point_format);
        f.gps_time = f.gps_time || format.gps_offset >= 0;
        f.rgb = f.rgb || format.rgb_offset >= 0;
    }
    return f;
}

PointFields point_fields(const dataset::Dataset& ds) {
    std::vector<std::uint32_t> all(ds.tiles.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    return point_fields(ds, all);
}

PointTable::PointTable(std::size_t capacity) : capacity_(capacity) {
    mapped_bytes_ = std::max<std::size_t>(capacity, 1) * sizeof(PointRecord);
    void* p = mmap(nullptr, mapped_bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    records_ = static_cast<PointRecord*>(p);
}

PointTable::~PointTable() {
    if (records_) munmap(records_, mapped_bytes_);
}

PointTable::PointTable(PointTable&& other) noexcept
    : records_(std::exchange(other.records_, nullptr)), size_(std::exchange(other.size_, 0)),
      capacity_(std::exchange(other.capacity_, 0)), mapped_bytes_(std::exchange(other.mapped_bytes_, 0)) {}

PointTable& PointTable::operator=(PointTable&& other) noexcept {
    if (this != &other) {
        if (records_) munmap(records_, mapped_bytes_);
        records_ = std::exchange(other.records_, nullptr);
        size_ = std::exchange(other.size_, 0);
        capacity_ = std::exchange(other.capacity_, 0);
        mapped_bytes_ = std::exchange(other.mapped_bytes_, 0);
    }
    return *this;
}

void PointTable::erase(std::size_t first, std::size_t n) {
    std::memmove(records_ + first, records_ + first + n, (size_ - first - n) * sizeof(PointRecord));
    size_ -= n;
}

}  // namespace lidarscout::python
