// GlTexture and GlPresenter: texture upload and framebuffer blit (libepoxy resolves the GL functions).
#include "viewer/app/gl_presenter.hpp"

#include <epoxy/gl.h>

namespace lidarscout::viewer::app {

GlTexture::GlTexture() { glGenTextures(1, &texture_); }

GlTexture::~GlTexture() { glDeleteTextures(1, &texture_); }

void GlTexture::upload(const render::RgbaImage& image) {
    if (image.width <= 0 || image.height <= 0) return;
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    if (image.width != width_ || image.height != height_) {
        width_ = image.width, height_ = image.height;
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width_, height_, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

GlPresenter::GlPresenter() { glGenFramebuffers(1, &framebuffer_); }

GlPresenter::~GlPresenter() { glDeleteFramebuffers(1, &framebuffer_); }

void GlPresenter::show(const render::RgbaImage& image, int fb_width, int fb_height) {
    if (image.width <= 0 || image.height <= 0) return;
    texture_.upload(image);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    if (texture_.width() != attached_width_ || texture_.height() != attached_height_) {  // reallocated
        attached_width_ = texture_.width(), attached_height_ = texture_.height();
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_.id(), 0);
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, texture_.width(), texture_.height(), 0, fb_height, fb_width, 0, GL_COLOR_BUFFER_BIT,
                      GL_LINEAR);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

}  // namespace lidarscout::viewer::app
