// A region's points for Python, by the clip's rules (pipelines/region_points.hpp: the tiles touching
// the area decoded in parallel, each point placed in the frame CRS's units, kept in the area when it
// passes the filter): written as they come into one PointTable (read_region), or handed out in tables
// of at most `batch` points by a reader thread that stays one table ahead, reading in smaller
// batches (kStreamReadPoints) so that the stream's memory stays a few tables (RegionStream).
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "pipelines/region_points.hpp"
#include "python/point_table.hpp"

namespace lidarscout::python {

// What the caller of `read` asks: an area (bounds or a polygon, or the whole dataset) and a filter.
struct RegionQuery {
    pipelines::Region region;
    PointFilter filter;
};

// `bounds` (xmin, ymin, xmax, ymax) or `polygon` (WKT, or the path of a GeoJSON file), not both; with
// neither, everywhere. `classes`, `returns`, `intensity` as the CLI's options take them
// (core/point_filter.hpp). Throws Error of stage `stage` naming what is wrong.
RegionQuery region_query(const std::optional<std::array<double, 4>>& bounds, const std::string& polygon,
                         const std::string& classes, const std::string& returns,
                         const std::string& intensity, const std::string& stage);

struct RegionRead {
    PointTable points;
    pipelines::RegionReadStats stats;
};

// Throws Error (stage "read") when no tile touches the area; a read that keeps no point is empty.
// `threads` 0: every core.
RegionRead read_region(const dataset::Dataset& ds, const RegionQuery& query, unsigned threads);

// Points a RegionStream's reads decode at once (pipelines::read_region_points' batch_points).
inline constexpr std::size_t kStreamReadPoints = std::size_t(1) << 18;

class RegionStream {
public:
    // Starts reading at once. Throws Error (stage "iter_read") when no tile touches the area.
    RegionStream(std::shared_ptr<const dataset::Dataset> ds, RegionQuery query, unsigned threads, std::size_t batch);
    ~RegionStream();  // stops the read (before its next batch) and waits for it
    RegionStream(const RegionStream&) = delete;
    RegionStream& operator=(const RegionStream&) = delete;

    // The next table (1 to batch points), waiting for it; empty at the end. Rethrows what ended the read.
    std::optional<PointTable> next();
    // The tiles the area touches, in dataset order.
    const std::vector<std::uint32_t>& tiles() const { return tiles_; }
    // What was read (complete once next() has returned empty).
    const pipelines::RegionReadStats& stats() const { return stats_; }

private:
    void run();
    void take(const pipelines::RegionBatch& batch);
    void hand_over();

    std::shared_ptr<const dataset::Dataset> ds_;
    RegionQuery query_;
    std::vector<std::uint32_t> tiles_;
    unsigned threads_;
    std::size_t batch_;
    PointTable filling_{0};
    pipelines::RegionReadStats stats_;

    std::mutex mutex_;
    std::condition_variable changed_;
    std::optional<PointTable> ready_;
    bool finished_ = false;
    std::exception_ptr failure_;
    std::atomic<bool> cancel_{false};
    std::thread thread_;
};

}  // namespace lidarscout::python
