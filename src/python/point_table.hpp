// The points the Python module hands out: one fixed 48-byte record per point (PointRecord; numpy
// sees it as a structured array whose fields are those the tiles have) in a PointTable that reserves
// address space for the most points it may hold and commits pages only as they are filled, so that
// the table's memory becomes the numpy array as it is (no copy, no reallocation while reading).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "dataset/dataset.hpp"
#include "las/point_format.hpp"

namespace lidarscout::python {

// x, y, z in the units of the dataset frame's CRS; tile is the index in Dataset::tiles.
struct PointRecord {
    double x = 0, y = 0, z = 0, gps_time = 0;
    std::uint32_t tile = 0;
    std::uint16_t intensity = 0, red = 0, green = 0, blue = 0;
    std::uint8_t return_number = 0, number_of_returns = 0, classification = 0, unused = 0;
};
static_assert(sizeof(PointRecord) == 48);

inline PointRecord point_record(const las::Point& p, double x, double y, double z, std::uint32_t tile) {
    return {x, y, z, p.gps_time, tile, p.intensity, p.rgb[0], p.rgb[1], p.rgb[2],
            p.return_number, p.number_of_returns, p.classification, 0};
}

// Which optional fields the points of `tiles` have: GPS time, colour (any tile's point format).
struct PointFields {
    bool gps_time = false, rgb = false;
};
PointFields point_fields(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles);
PointFields point_fields(const dataset::Dataset& ds);  // of every tile

class PointTable {
public:
    // Room for `capacity` records (address space only: pages are committed as records are written).
    // Throws std::bad_alloc when the address space cannot be had.
    explicit PointTable(std::size_t capacity);
    ~PointTable();
    PointTable(PointTable&& other) noexcept;
    PointTable& operator=(PointTable&& other) noexcept;
    PointTable(const PointTable&) = delete;
    PointTable& operator=(const PointTable&) = delete;

    std::size_t size() const { return size_; }
    std::size_t capacity() const { return capacity_; }
    std::size_t room() const { return capacity_ - size_; }
    PointRecord* data() { return records_; }
    const PointRecord* data() const { return records_; }
    void push_back(const PointRecord& r) { records_[size_++] = r; }  // size() < capacity()
    // Marks `n` more records as written (by a caller that filled data() + size() on).
    void grow(std::size_t n) { size_ += n; }
    // Drops the records [first, first + n), moving the later ones down.
    void erase(std::size_t first, std::size_t n);

private:
    PointRecord* records_ = nullptr;
    std::size_t size_ = 0, capacity_ = 0, mapped_bytes_ = 0;
};

}  // namespace lidarscout::python
