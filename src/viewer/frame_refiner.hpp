// Progressive refinement of still frames. While the camera moves, frames draw the LOD blocks at
// the style's spacing (about one point per pixel, fast). A still camera whose snapshot changes
// while points for it are still loading gets half that spacing; new data for a still view is
// redrawn at most every `data_interval` and, while points load, at most a tenth of the time,
// refined frames counted (drawing takes every core, and a loading view leaves them to the
// decoders: the picture it draws is soon out of date), else a fifth; a `data_interval` of 0
// redraws every change.
// The refined frame draws the blocks with every point held (or, above a point cap, the finest
// spacing under it), the picture a converged view should equal; after that the same image is
// given back until the camera, the snapshot or the style changes. It is drawn once the camera has
// stayed still for a settling time and nothing is loading (new data then is drawn refined at
// once), or, while loading goes on, once the snapshot too has not changed for `loading_settle`.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "viewer/scene_snapshot.hpp"

namespace lidarscout::viewer {

// The spacing (pixels) at which a refined frame draws `blocks`: 0 (every point held) when at
// most `max_points` points are in view, else the smallest power-of-two fraction of `coarse_px`
// that stays under the cap (`coarse_px` itself at worst).
double refined_spacing(const LodBlocks& blocks, const render::Camera& camera, double coarse_px,
                       std::uint64_t max_points);

class FrameRefiner {
public:
    explicit FrameRefiner(std::chrono::milliseconds settle = std::chrono::milliseconds(250),
                          std::uint64_t max_points = 24'000'000,
                          std::chrono::milliseconds data_interval = std::chrono::milliseconds(100),
                          std::chrono::milliseconds loading_settle = std::chrono::milliseconds(2000))
        : settle_(settle), max_points_(max_points), data_interval_(data_interval), loading_settle_(loading_settle) {}

    // The frame for this camera and snapshot (see above); `loading`: points for this camera are
    // still being loaded (ask before taking the snapshot, so that a snapshot taken when nothing
    // loads holds everything). Styles are compared by their colour mode, point sizes, eye-dome
    // lighting, LOD spacing and backend; call invalidate() after other style changes.
    const RenderedScene& draw(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers = {}, bool loading = false);
    void invalidate() { last_.reset(); }
    // True when the last frame drawn was a refined one.
    bool refined() const { return refined_; }

private:
    struct Key {
        render::Camera camera;
        std::uint64_t version = 0;
        SceneStyle style;
        SceneLayers layers;
    };
    static bool same(const Key& a, const Key& b);
    static bool same_view(const Key& a, const Key& b);  // all but the snapshot's version
    // How long a still view waits between two frames (`loading`: points are still loading).
    std::chrono::steady_clock::duration interval(bool loading) const;

    std::chrono::milliseconds settle_;
    std::uint64_t max_points_;
    std::chrono::milliseconds data_interval_;
    std::chrono::milliseconds loading_settle_;
    std::optional<Key> last_;                 // of the last frame drawn
    std::optional<std::uint64_t> seen_version_;  // the last snapshot version seen (drawn or not)
    std::chrono::steady_clock::time_point view_changed_at_, data_changed_at_, drawn_at_;
    std::chrono::steady_clock::duration draw_time_{};  // of the last frame drawn
    bool refined_ = false;
    RenderedScene frame_;
};

}  // namespace lidarscout::viewer
