// Shows the software rasterizer's image in the window: the only OpenGL the viewer uses besides
// the GUI. The RGBA image is uploaded into a texture and blitted onto the window's framebuffer
// (flipped: image row 0 is the top, GL's row 0 the bottom). Needs a current GL >= 3.0 context.
#pragma once

#include <cstdint>

#include "render/resolve.hpp"

namespace lidarscout::viewer::app {

class GlPresenter {
public:
    GlPresenter();
    ~GlPresenter();
    GlPresenter(const GlPresenter&) = delete;
    GlPresenter& operator=(const GlPresenter&) = delete;

    // Draws `image` stretched over the window's framebuffer (fb_width x fb_height pixels).
    void show(const render::RgbaImage& image, int fb_width, int fb_height);

private:
    unsigned texture_ = 0, framebuffer_ = 0;
    int width_ = 0, height_ = 0;
};

}  // namespace lidarscout::viewer::app
