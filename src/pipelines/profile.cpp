// Profiles: the corridor test, the reading of its points and their CSV.
#include "pipelines/profile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "io/file.hpp"
#include "io/output_file.hpp"

namespace lidarscout::pipelines {

double Corridor::length() const { return std::hypot(x1 - x0, y1 - y0); }

double Corridor::along(double x, double y) const {
    return ((x - x0) * (x1 - x0) + (y - y0) * (y1 - y0)) / length();
}

double Corridor::across(double x, double y) const {
    return ((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)) / length();
}

bool Corridor::contains(double x, double y) const {
    const double a = along(x, y);
    return a >= 0 && a <= length() && std::abs(across(x, y)) <= width / 2;
}

bool Corridor::touches_box(double bx0, double by0, double bx1, double by1) const {
    // The box's corners projected on the corridor's axes must overlap [0, length] and [-w/2, w/2].
    double a_lo = INFINITY, a_hi = -INFINITY, c_lo = INFINITY, c_hi = -INFINITY;
    for (const double x : {bx0, bx1}) {
        for (const double y : {by0, by1}) {
            a_lo = std::min(a_lo, along(x, y)), a_hi = std::max(a_hi, along(x, y));
            c_lo = std::min(c_lo, across(x, y)), c_hi = std::max(c_hi, across(x, y));
        }
    }
    if (a_hi < 0 || a_lo > length() || c_hi < -width / 2 || c_lo > width / 2) return false;
    // The rectangle's extent on the box's axes.
    const double h = width / 2, nx = -(y1 - y0) / length() * h, ny = (x1 - x0) / length() * h;
    const double xs[4] = {x0 + nx, x0 - nx, x1 + nx, x1 - nx}, ys[4] = {y0 + ny, y0 - ny, y1 + ny, y1 - ny};
    return *std::max_element(xs, xs + 4) >= bx0 && *std::min_element(xs, xs + 4) <= bx1 &&
           *std::max_element(ys, ys + 4) >= by0 && *std::min_element(ys, ys + 4) <= by1;
}

Region corridor_region(const Corridor& c) {
    if (!(c.length() > 0)) throw Error::in_stage("profile", "--line: the two ends are the same point");
    if (!(c.width > 0)) throw Error::in_stage("profile", "--width must be positive");
    const double h = c.width / 2;
    Region r = box_region(std::min(c.x0, c.x1) - h, std::min(c.y0, c.y1) - h, std::max(c.x0, c.x1) + h,
                          std::max(c.y0, c.y1) + h);
    r.contains = [c](double x, double y) { return c.contains(x, y); };
    r.touches = [c](const dataset::Bounds& b) { return c.touches_box(b.min_x, b.min_y, b.max_x, b.max_y); };
    return r;
}

Profile read_profile(const dataset::Dataset& ds, const Corridor& corridor, const PointFilter& filter,
                     ThreadPool& pool, const ReadWatch& watch, const ProfilePointsFn& points) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    const Region region = corridor_region(corridor);
    Profile profile;
    const auto add = [&](const RegionBatch& b) {
        if (profile.points.empty()) profile.seconds_to_first_points = since();
        const std::size_t first = profile.points.size();
        for (const auto& p : b.points) {
            profile.points.push_back({corridor.along(p.x, p.y), p.x, p.y, p.z, p.point.intensity,
                                      p.point.classification, p.point.return_number, p.point.number_of_returns,
                                      b.tile});
        }
        if (points) points(std::span(profile.points).subspan(first));
    };
    profile.read = read_region_points(ds, tiles_touching(ds, region), region, filter, pool, add, watch);
    profile.seconds = since();
    return profile;
}

void require_profile_points(const dataset::Dataset& ds, const Corridor& corridor, const PointFilter& filter,
                            const Profile& profile, ThreadPool& pool) {
    if (!profile.points.empty()) return;
    const Region region = corridor_region(corridor);
    const std::vector<std::uint32_t> tiles = tiles_touching(ds, region);
    require_touched_tiles(ds, tiles, region, "profile", kCorridor);
    require_kept_points(ds, tiles, region, filter, profile.read, pool, "profile", kCorridor);
}

void write_profile_csv(const std::string& path, const dataset::Dataset& ds, const Profile& profile) {
    io::AtomicOutputFile out(path);
    std::string text = "distance,x,y,z,class,intensity,return,returns,source_file\n";
    const auto flush = [&] {
        out.write(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
        text.clear();
    };
    for (const auto& p : profile.points) {
        fmt::format_to(std::back_inserter(text), "{:.3f},{:.3f},{:.3f},{:.3f},{},{},{},{},\"{}\"\n", p.distance, p.x,
                       p.y, p.z, p.classification, p.intensity, p.return_number, p.number_of_returns,
                       io::display_path(ds.tiles[p.tile].tile.path()));
        if (text.size() > (1u << 20)) flush();
    }
    flush();
    out.commit();
}

}  // namespace lidarscout::pipelines
