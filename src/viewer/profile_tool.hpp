// The viewer's profile tool without window code: the corridor (two clicked points and a width, or
// `view --profile x0,y0,x1,y1,width` in the dataset CRS's units), read in the background with
// pipelines::read_profile (every full-resolution point of the tiles it touches, not only those
// held, filtered as drawn) and drawn as an image (distance against height, pipelines/profile_image)
// again as the read grows, at most a few times a second; the lowest height along the line, for the
// corridor drawn over the scene. Cancelled when it is closed or replaced (between batches).
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "pipelines/profile.hpp"
#include "pipelines/profile_image.hpp"
#include "render/resolve.hpp"
#include "viewer/background_reads.hpp"
#include "viewer/picking.hpp"

namespace lidarscout::viewer {

// "x0,y0,x1,y1,width" (`view --profile`): the line and the corridor's full width, in the dataset
// CRS's units. Throws lidarscout::Error (stage "view") for another count of numbers, a width that
// is not positive or two ends that are the same point.
pipelines::Corridor parse_corridor(const std::string& text);

// The corridor from a to b (world metres, as picked) `width` wide, in the frame CRS's units (`width`
// is in those units already).
pipelines::Corridor corridor_between(const PickedPoint& a, const PickedPoint& b, double width,
                                     const dataset::Frame& frame);

// How the profile is drawn: its colours and the image's size in pixels.
struct ProfileLook {
    pipelines::ProfileColours colours = pipelines::ProfileColours::Classification;
    double ramp_min = NAN, ramp_max = NAN;  // the elevation ramp's range (profile_image), the frame CRS's units
    int width = 960, height = 360;
    bool operator==(const ProfileLook&) const = default;
};

// Where a profile's read stands.
struct ProfileStatus {
    ReadProgress read;
    std::uint64_t points = 0;  // in the corridor so far
    bool done = false;         // read to the end (or failed)
    std::string error;         // why it failed ("" when it did not)
};

// The lowest height in each of `bins` equal pieces of the line (the frame CRS's units; NaN where
// no point fell), gaps filled from the nearest piece with points: the corridor drawn over the scene
// follows the ground. All NaN without points.
std::vector<double> lowest_along(std::span<const pipelines::ProfilePoint> points, double length, std::size_t bins);

// One profile read on its own thread. Destroying it cancels the read and waits for the thread.
class ProfileJob {
public:
    static constexpr std::size_t kLineBins = 64;

    // `ds` must outlive the job; `threads` decode (a pool of its own: the frame's pool stays free).
    ProfileJob(const dataset::Dataset& ds, const pipelines::Corridor& corridor, const PointFilter& filter,
               const ProfileLook& look, unsigned threads);
    ~ProfileJob();
    ProfileJob(const ProfileJob&) = delete;
    ProfileJob& operator=(const ProfileJob&) = delete;

    // Stops the read before its next batch (status().done then comes soon: destroying the job no
    // longer waits for a batch).
    void cancel() { counters_.cancel(); }
    const pipelines::Corridor& corridor() const { return corridor_; }
    const PointFilter& filter() const { return filter_; }
    ProfileStatus status() const;
    // Draws it again with another look (on the job's thread).
    void set_look(const ProfileLook& look);
    // The image drawn last when it is newer than `seen` (which is updated), else null.
    std::shared_ptr<const render::RgbaImage> image_since(std::uint64_t& seen) const;
    // What the image drawn last spans (its axes' range and grid steps: the image has no text).
    pipelines::ProfileImageScale scale() const;
    // The whole profile once read (null before, and after a failure).
    std::shared_ptr<const pipelines::Profile> profile() const;
    // kLineBins lowest heights along the line (lowest_along), from the points read so far.
    std::vector<double> line_heights() const;
    // Blocks until the read is done (scripted use).
    void wait() const;

private:
    void run();
    void draw(const pipelines::Profile& profile);

    const dataset::Dataset& ds_;
    const pipelines::Corridor corridor_;
    const PointFilter filter_;
    const unsigned threads_;
    ReadCounters counters_;
    mutable std::mutex mutex_;  // guards what follows
    mutable std::condition_variable changed_;
    ProfileLook look_;
    bool look_changed_ = false, stop_ = false, done_ = false;
    std::uint64_t points_ = 0, generation_ = 0;
    std::string error_;
    std::shared_ptr<const render::RgbaImage> image_;
    pipelines::ProfileImageScale scale_;
    std::shared_ptr<const pipelines::Profile> profile_;
    std::vector<double> line_heights_;
    std::thread thread_;  // last: started when the rest is set
};

}  // namespace lidarscout::viewer
