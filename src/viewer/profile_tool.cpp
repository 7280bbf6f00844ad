// The profile tool: the corridor's text and clicks, and the job that reads and draws it.
#include "viewer/profile_tool.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/thread_pool.hpp"

namespace lidarscout::viewer {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kRedraw = std::chrono::milliseconds(250);  // while the read grows, at most 4 images a second

Error corridor_error(const std::string& text, const std::string& why) {
    return Error::in_stage("view", "--profile wants x0,y0,x1,y1,width in the dataset CRS's units, not '" + text +
                                       "': " + why);
}

}  // namespace

pipelines::Corridor parse_corridor(const std::string& text) {
    std::vector<double> v;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t end = std::min(text.find(',', at), text.size());
        double x = 0;
        const auto r = std::from_chars(text.data() + at, text.data() + end, x);
        if (r.ec != std::errc() || r.ptr != text.data() + end || !std::isfinite(x)) {
            throw corridor_error(text, "'" + text.substr(at, end - at) + "' is not a number");
        }
        v.push_back(x);
        at = end + 1;
    }
    if (v.size() != 5) throw corridor_error(text, std::to_string(v.size()) + " numbers");
    const pipelines::Corridor c{v[0], v[1], v[2], v[3], v[4]};
    if (!(c.width > 0)) throw corridor_error(text, "the width must be positive");
    if (!(c.length() > 0)) throw corridor_error(text, "the two ends are the same point");
    return c;
}

pipelines::Corridor corridor_between(const PickedPoint& a, const PickedPoint& b, double width,
                                     const dataset::Frame& frame) {
    const double f = frame.xy_to_metres;
    return {a.x / f, a.y / f, b.x / f, b.y / f, width};
}

std::vector<double> lowest_along(std::span<const pipelines::ProfilePoint> points, double length, std::size_t bins) {
    std::vector<double> low(bins, NAN);
    if (bins == 0 || !(length > 0)) return low;
    for (const auto& p : points) {
        const auto k = static_cast<std::size_t>(std::clamp(p.distance / length * double(bins), 0.0, bins - 1.0));
        if (!(p.z >= low[k])) low[k] = p.z;  // NaN compares false: the first point sets it
    }
    std::vector<double> filled = low;
    for (std::size_t k = 0; k < bins; ++k) {
        if (!std::isnan(low[k])) continue;
        for (std::size_t d = 1; d < bins; ++d) {  // the nearest piece with points, the lower side first
            if (k >= d && !std::isnan(low[k - d])) { filled[k] = low[k - d]; break; }
            if (k + d < bins && !std::isnan(low[k + d])) { filled[k] = low[k + d]; break; }
        }
    }
    return filled;
}

ProfileJob::ProfileJob(const dataset::Dataset& ds, const pipelines::Corridor& corridor, const PointFilter& filter,
                       const ProfileLook& look, unsigned threads)
    : ds_(ds), corridor_(corridor), filter_(filter), threads_(std::max(1u, threads)), look_(look),
      thread_([this] { run(); }) {}

ProfileJob::~ProfileJob() {
    counters_.cancel();
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    changed_.notify_all();
    thread_.join();
}

ProfileStatus ProfileJob::status() const {
    ProfileStatus s;
    s.read = counters_.progress();
    const std::lock_guard lock(mutex_);
    s.points = points_, s.done = done_, s.error = error_;
    return s;
}

void ProfileJob::set_look(const ProfileLook& look) {
    {
        const std::lock_guard lock(mutex_);
        if (look == look_) return;
        look_ = look, look_changed_ = true;
    }
    changed_.notify_all();
}

std::shared_ptr<const render::RgbaImage> ProfileJob::image_since(std::uint64_t& seen) const {
    const std::lock_guard lock(mutex_);
    if (generation_ == seen) return nullptr;
    seen = generation_;
    return image_;
}

pipelines::ProfileImageScale ProfileJob::scale() const {
    const std::lock_guard lock(mutex_);
    return scale_;
}

std::shared_ptr<const pipelines::Profile> ProfileJob::profile() const {
    const std::lock_guard lock(mutex_);
    return profile_;
}

std::vector<double> ProfileJob::line_heights() const {
    const std::lock_guard lock(mutex_);
    return line_heights_;
}

void ProfileJob::wait() const {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return done_; });
}

void ProfileJob::draw(const pipelines::Profile& profile) {
    ProfileLook look;
    {
        const std::lock_guard lock(mutex_);
        look = look_;
    }
    pipelines::ProfileImageScale scale;
    auto image = std::make_shared<const render::RgbaImage>(
        pipelines::profile_image(profile, corridor_, look.width, look.height, &scale, look.colours, look.ramp_min,
                                 look.ramp_max));
    auto heights = lowest_along(profile.points, corridor_.length(), kLineBins);
    const std::lock_guard lock(mutex_);
    image_ = std::move(image), line_heights_ = std::move(heights), scale_ = scale;
    ++generation_;
}

void ProfileJob::run() {
    try {
        ThreadPool pool(threads_);
        pipelines::Profile shown;  // the points so far, drawn while the read grows
        auto drawn = Clock::now() - kRedraw;
        const auto grow = [&](std::span<const pipelines::ProfilePoint> points) {
            shown.points.insert(shown.points.end(), points.begin(), points.end());
            {
                const std::lock_guard lock(mutex_);
                points_ = shown.points.size();
            }
            if (Clock::now() - drawn < kRedraw) return;
            draw(shown);
            drawn = Clock::now();
        };
        auto profile = std::make_shared<pipelines::Profile>(
            pipelines::read_profile(ds_, corridor_, filter_, pool, counters_.watch(), grow));
        shown = {};
        if (!profile->read.cancelled) {
            draw(*profile);
            const std::lock_guard lock(mutex_);
            points_ = profile->points.size();
            profile_ = std::move(profile);
        }
    } catch (const Error& e) {
        const std::lock_guard lock(mutex_);
        error_ = e.what();
    } catch (const std::exception& e) {  // out of memory: this profile only
        const std::lock_guard lock(mutex_);
        error_ = std::string("profile: ") + e.what();
    }
    std::unique_lock lock(mutex_);
    done_ = true;
    changed_.notify_all();
    while (true) {  // drawn again when the look changes, until the job is closed
        changed_.wait(lock, [this] { return stop_ || look_changed_; });
        if (stop_) return;
        look_changed_ = false;
        const auto profile = profile_;
        lock.unlock();
        if (profile) draw(*profile);
        lock.lock();
    }
}

}  // namespace lidarscout::viewer
