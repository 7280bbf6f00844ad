// Shows the software rasterizer's image in the window: with the GUI's, the only OpenGL the viewer
// uses. An RGBA image is uploaded into a texture (GlTexture: also what ImGui::Image shows, e.g. a
// profile's plot) and, for the picture, blitted onto the window's framebuffer (flipped: image row 0
// is the top, GL's row 0 the bottom). Needs a current GL >= 3.0 context.
#pragma once

#include <cstdint>

#include "render/resolve.hpp"

namespace lidarscout::viewer::app {

// One RGBA8 texture holding the last image uploaded (linear filtering).
class GlTexture {
public:
    GlTexture();
    ~GlTexture();
    GlTexture(const GlTexture&) = delete;
    GlTexture& operator=(const GlTexture&) = delete;

    void upload(const render::RgbaImage& image);  // an empty image is ignored
    unsigned id() const { return texture_; }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    unsigned texture_ = 0;
    int width_ = 0, height_ = 0;
};

class GlPresenter {
public:
    GlPresenter();
    ~GlPresenter();
    GlPresenter(const GlPresenter&) = delete;
    GlPresenter& operator=(const GlPresenter&) = delete;

    // Draws `image` stretched over the window's framebuffer (fb_width x fb_height pixels).
    void show(const render::RgbaImage& image, int fb_width, int fb_height);

private:
    GlTexture texture_;
    unsigned framebuffer_ = 0;
    int attached_width_ = 0, attached_height_ = 0;  // the texture's size when attached to framebuffer_
};

}  // namespace lidarscout::viewer::app
