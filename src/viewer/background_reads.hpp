// What the viewer reads and writes beside its frames, without window code: the counters a
// background read of full-resolution points reports into (points read, tiles done, a cancel flag,
// as pipelines::ReadWatch), and one file exported on its own thread (the area's points clipped to
// LAZ, a profile's CSV, PNG or LAZ), its output checked first against the dataset's inputs as the
// command line checks its outputs (io/output_check.hpp) and written through a temporary name.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "io/output_check.hpp"
#include "pipelines/profile.hpp"
#include "pipelines/region_points.hpp"

namespace lidarscout::viewer {

// A snapshot of ReadCounters.
struct ReadProgress {
    std::uint64_t points_read = 0, points_total = 0;
    std::size_t tiles_done = 0, tiles_total = 0;
    // "12.3 of 45.6 M points read, 2 of 5 tiles"
    std::string line() const;
};

// Counters a read on another thread updates and the frame reads, and its cancel flag.
class ReadCounters {
public:
    pipelines::ReadWatch watch();  // refers to this object: it must outlive the read
    ReadProgress progress() const;
    void cancel() { cancel_ = true; }
    bool cancelled() const { return cancel_; }

private:
    std::atomic<std::uint64_t> points_read_{0}, points_total_{0};
    std::atomic<std::size_t> tiles_done_{0}, tiles_total_{0};
    std::atomic<bool> cancel_{false};
};

// Refuses (lidarscout::Error) an export to `path` that the command line would refuse: one of the
// `inputs` (the paths the dataset was opened from), a tile's name inside an input folder, an
// extension that `kind` does not take, a folder that is missing or not writable.
void check_export(const std::string& path, io::OutputKind kind, const std::vector<std::string>& inputs);

// One file written on its own thread; destroying it cancels the write (between batches of points)
// and waits for the thread: a cancelled or failed write leaves no file.
class ExportTask {
public:
    // `write` runs on the thread with the counters to report into; it returns the line shown when it
    // is done ("clip: 123 points written to F") and throws lidarscout::Error when it fails.
    using Write = std::function<std::string(ReadCounters&)>;
    ExportTask(std::string path, Write write);
    ~ExportTask();
    ExportTask(const ExportTask&) = delete;
    ExportTask& operator=(const ExportTask&) = delete;

    const std::string& path() const { return path_; }
    bool done() const { return done_; }
    bool failed() const;
    // The progress while it runs, then its result line (or "FILE: CAUSE" when it failed).
    std::string status() const;
    void cancel() { counters_.cancel(); }

private:
    std::string path_;
    ReadCounters counters_;
    mutable std::mutex mutex_;
    std::string result_;
    bool failed_ = false;
    std::atomic<bool> done_{false};
    std::thread thread_;
};

// The area's points (polygon in the dataset CRS's units) kept by `filter`, clipped to `path`
// (.laz or .las) as `lidarscout clip` writes them. `ds` must outlive the task.
std::unique_ptr<ExportTask> export_clip(const dataset::Dataset& ds, const std::string& path,
                                        pipelines::Region region, const PointFilter& filter, unsigned threads);

// A profile written to `path`: .csv (write_profile_csv) or .png (the command line's 1600 x 600
// image) from `profile`, the profile read; .laz or .las the corridor's points as `profile -o`
// writes them (read again). `ds` must outlive the task.
std::unique_ptr<ExportTask> export_profile(const dataset::Dataset& ds, const std::string& path,
                                           const pipelines::Corridor& corridor, const PointFilter& filter,
                                           std::shared_ptr<const pipelines::Profile> profile, unsigned threads);

}  // namespace lidarscout::viewer
