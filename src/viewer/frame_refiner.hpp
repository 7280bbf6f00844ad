// Progressive refinement of still frames. While the camera moves, frames draw the LOD blocks at
// the style's spacing (about one point per pixel, fast); a still camera whose snapshot changes
// (data arriving) gets half that spacing, redrawn at most every `data_interval` and at most a
// fifth of the time (a loading view leaves the cores to the decoders); a `data_interval` of 0
// redraws every change.
// Once a camera and a snapshot have been drawn that way and stayed unchanged for a settling time
// (so that a scheduler still loading keeps its cores for decoding), the next frame draws the blocks with every point
// held (or, above a point cap, the finest spacing under it), the picture a converged view should equal; after that the
// same image is given back until the camera, the snapshot or the style changes.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "viewer/scheduler_snapshot.hpp"

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
                          std::chrono::milliseconds data_interval = std::chrono::milliseconds(100))
        : settle_(settle), max_points_(max_points), data_interval_(data_interval) {}

    // The frame for this camera and snapshot (see above). Styles are compared by their colour
    // mode, point sizes, eye-dome lighting, LOD spacing and backend; call invalidate() after
    // other style changes.
    const RenderedScene& draw(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers = {});
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

    std::chrono::milliseconds settle_;
    std::uint64_t max_points_;
    std::chrono::milliseconds data_interval_;
    std::optional<Key> last_;
    std::chrono::steady_clock::time_point changed_at_, drawn_at_;
    std::chrono::steady_clock::duration draw_time_{};  // of the last frame that was not refined
    bool refined_ = false;
    RenderedScene frame_;
};

}  // namespace lidarscout::viewer
