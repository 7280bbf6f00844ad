// Background reads and exports: the counters, the output check, the export thread.
#include "viewer/background_reads.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/file_search.hpp"
#include "pipelines/clip.hpp"
#include "pipelines/profile_image.hpp"
#include "render/png_writer.hpp"

namespace lidarscout::viewer {
namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// "clip: 123 points written to F" with the points left out of unreadable chunks or tiles, if any.
std::string written_line(const char* what, std::uint64_t points, const std::string& path,
                         const pipelines::RegionReadStats& read) {
    std::string line = fmt::format("{}: {} points written to {}", what, points, path);
    if (read.points_skipped) line += fmt::format(" ({} points in unreadable chunks or tiles left out)",
                                                 read.points_skipped);
    return line;
}

// The points of `region` clipped to `path`; `what` names the line ("clip: N points written to F").
std::unique_ptr<ExportTask> clip_task(const dataset::Dataset& ds, const std::string& path, pipelines::Region region,
                                      const PointFilter& filter, unsigned threads, const char* what) {
    return std::make_unique<ExportTask>(path, [&ds, path, region = std::move(region), filter, threads,
                                               what](ReadCounters& counters) {
        ThreadPool pool(threads);
        const pipelines::ClipResult r = pipelines::clip_to_file(ds, {path, region, filter, counters.watch()}, pool);
        return written_line(what, r.points_written, path, r.read);
    });
}

}  // namespace

std::string ReadProgress::line() const {
    return fmt::format("{:.1f} of {:.1f} M points read, {} of {} tiles", points_read / 1e6, points_total / 1e6,
                       tiles_done, tiles_total);
}

pipelines::ReadWatch ReadCounters::watch() {
    pipelines::ReadWatch w;
    w.progress = [this](std::uint64_t done, std::uint64_t total) { points_read_ = done, points_total_ = total; };
    w.tiles = [this](std::size_t done, std::size_t total) { tiles_done_ = done, tiles_total_ = total; };
    w.cancel = &cancel_;
    return w;
}

ReadProgress ReadCounters::progress() const {
    return {points_read_.load(), points_total_.load(), tiles_done_.load(), tiles_total_.load()};
}

void check_export(const std::string& path, io::OutputKind kind, const std::vector<std::string>& inputs) {
    if (path.empty()) throw Error::in_stage("view", "give the export a file name");
    io::check_outputs({io::OutputTarget{path, "export", kind}}, dataset::local_inputs(inputs));
}

ExportTask::ExportTask(std::string path, Write write) : path_(std::move(path)) {
    thread_ = std::thread([this, write = std::move(write)] {
        std::string line;
        bool failed = false;
        try {
            line = write(counters_);
        } catch (const Error& e) {
            line = e.what(), failed = true;
        } catch (const std::exception& e) {
            line = path_ + ": " + e.what(), failed = true;  // out of memory: this export only
        }
        {
            const std::lock_guard lock(mutex_);
            result_ = std::move(line), failed_ = failed;
        }
        done_ = true;
    });
}

ExportTask::~ExportTask() {
    counters_.cancel();
    thread_.join();
}

bool ExportTask::failed() const {
    const std::lock_guard lock(mutex_);
    return failed_;
}

std::string ExportTask::status() const {
    if (!done_) {
        const ReadProgress read = counters_.progress();
        return "writing " + path_ + (read.points_total ? ": " + read.line() : "");
    }
    const std::lock_guard lock(mutex_);
    return result_;
}

std::unique_ptr<ExportTask> export_clip(const dataset::Dataset& ds, const std::string& path,
                                        pipelines::Region region, const PointFilter& filter, unsigned threads) {
    return clip_task(ds, path, std::move(region), filter, threads, "clip");
}

std::unique_ptr<ExportTask> export_profile(const dataset::Dataset& ds, const std::string& path,
                                           const pipelines::Corridor& corridor, const PointFilter& filter,
                                           std::shared_ptr<const pipelines::Profile> profile, unsigned threads) {
    const std::string ext = lower_extension(path);
    if (ext == ".laz" || ext == ".las") {
        return clip_task(ds, path, pipelines::corridor_region(corridor), filter, threads, "profile");
    }
    if (!profile) throw Error::in_stage("view", "the profile is still being read");
    return std::make_unique<ExportTask>(path, [&ds, path, corridor, profile, ext](ReadCounters&) {
        if (ext == ".png") render::write_png(path, pipelines::profile_image(*profile, corridor,
                                                                            pipelines::profile_png_options(ds.frame)));
        else pipelines::write_profile_csv(path, ds, *profile);
        return written_line("profile", profile->points.size(), path, profile->read);
    });
}

}  // namespace lidarscout::viewer
