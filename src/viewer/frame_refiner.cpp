// FrameRefiner: the fast frame while anything changes, one refined frame once all is still and loaded.
#include "viewer/frame_refiner.hpp"

#include <algorithm>

namespace lidarscout::viewer {
namespace {

std::uint64_t points_in(const LodBlocks& blocks, const render::Camera& camera, double spacing_px) {
    std::uint64_t n = 0;
    for (const auto& b : lod_batches(blocks, camera, spacing_px)) n += b.points.size();
    return n;
}

bool same_camera(const render::Camera& a, const render::Camera& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z && a.yaw_deg == b.yaw_deg && a.pitch_deg == b.pitch_deg &&
           a.fov_deg == b.fov_deg && a.width == b.width && a.height == b.height && a.near_m == b.near_m &&
           a.far_m == b.far_m;
}

}  // namespace

double refined_spacing(const LodBlocks& blocks, const render::Camera& camera, double coarse_px,
                       std::uint64_t max_points) {
    if (points_in(blocks, camera, 0) <= max_points) return 0;
    double best = coarse_px;
    for (double s = coarse_px / 2; s >= coarse_px / 16 && points_in(blocks, camera, s) <= max_points; s /= 2) best = s;
    return best;
}

bool FrameRefiner::same(const Key& a, const Key& b) { return a.version == b.version && same_view(a, b); }

bool FrameRefiner::same_view(const Key& a, const Key& b) {
    const SceneStyle &s = a.style, &t = b.style;
    return same_camera(a.camera, b.camera) && s.colour.mode == t.colour.mode &&
           s.point_size == t.point_size && s.adaptive_point_size == t.adaptive_point_size &&
           s.chunk_point_size == t.chunk_point_size &&
           s.resolve.edl_strength == t.resolve.edl_strength && s.lod_spacing_px == t.lod_spacing_px &&
           s.backend == t.backend && a.layers.heightmaps == b.layers.heightmaps &&
           a.layers.chunk_points == b.layers.chunk_points && a.layers.full_points == b.layers.full_points;
}

std::chrono::steady_clock::duration FrameRefiner::interval(bool loading) const {
    if (data_interval_.count() == 0) return std::chrono::steady_clock::duration::zero();
    const int share = loading ? 10 : 5;  // drawing takes at most this fraction of the time
    return std::max<std::chrono::steady_clock::duration>(data_interval_, (share - 1) * draw_time_);
}

const RenderedScene& FrameRefiner::draw(const SceneSnapshot& snapshot, const render::Camera& camera,
                                        const SceneStyle& style, ThreadPool& pool, const SceneLayers& layers,
                                        bool loading) {
    const Key key{camera, snapshot.version, style, layers};
    const auto now = std::chrono::steady_clock::now();
    const bool view_same = last_ && same_view(*last_, key);
    if (!view_same) view_changed_at_ = now;
    if (!seen_version_ || *seen_version_ != key.version) data_changed_at_ = now, seen_version_ = key.version;
    const bool same_key = view_same && last_->version == key.version;
    if (same_key && refined_) return frame_;
    const bool refine = view_same && now - view_changed_at_ >= settle_ &&
                        (!loading || now - data_changed_at_ >= loading_settle_);
    if (same_key && !refine) return frame_;
    // New data for a still view is drawn at most every interval: a moving camera is never held
    // back, nor the refined frame of a view that settled (drawn once).
    if (view_same && !same_key && now - drawn_at_ < interval(loading)) return frame_;
    SceneStyle drawn = style;
    if (refine && style.lod_spacing_px > 0) {
        drawn.lod_spacing_px = refined_spacing(snapshot.full_points, camera, style.lod_spacing_px, max_points_);
    } else if (view_same) {
        drawn.lod_spacing_px = style.lod_spacing_px / 2;  // a still camera while data arrives: finer already
    }
    frame_ = render_snapshot(snapshot, camera, drawn, pool, layers);
    refined_ = refine;
    last_ = key;
    drawn_at_ = now;
    draw_time_ = std::chrono::steady_clock::now() - now;
    return frame_;
}

}  // namespace lidarscout::viewer
