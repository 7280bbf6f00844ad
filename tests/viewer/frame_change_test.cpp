// viewer/frame_change: a frame is presented when its image, its panels or the window's size change, or
// its refresh interval has passed; a frame that changes nothing is not.
#include "viewer/frame_change.hpp"

#include <gtest/gtest.h>

namespace lidarscout::viewer {
namespace {

using namespace std::chrono_literals;

render::RgbaImage image(int w, int h, std::uint32_t colour) {
    render::RgbaImage im;
    im.width = w, im.height = h;
    im.pixels.assign(static_cast<std::size_t>(w) * h, colour);
    return im;
}

TEST(FrameChange, OnlyAFrameThatChangesWhatTheWindowShowsIsPresented) {
    FrameChange change(500ms);
    const auto t0 = std::chrono::steady_clock::now();
    render::RgbaImage picture = image(64, 48, 7);
    EXPECT_TRUE(change.present(picture, 1, 640, 480, t0)) << "the first frame";
    EXPECT_FALSE(change.present(picture, 1, 640, 480, t0 + 16ms)) << "the same picture and panels";
    picture.pixels[64 * 47 + 63] = 8;  // one pixel, the last
    EXPECT_TRUE(change.present(picture, 1, 640, 480, t0 + 32ms));
    EXPECT_FALSE(change.present(picture, 1, 640, 480, t0 + 48ms));
    EXPECT_TRUE(change.present(picture, 2, 640, 480, t0 + 64ms)) << "the panels changed";
    EXPECT_TRUE(change.present(picture, 2, 641, 480, t0 + 80ms)) << "the window was resized";
    EXPECT_TRUE(change.present(image(32, 24, 7), 2, 641, 480, t0 + 96ms)) << "another image size";
    EXPECT_FALSE(change.present(image(32, 24, 7), 2, 641, 480, t0 + 500ms));
    EXPECT_TRUE(change.present(image(32, 24, 7), 2, 641, 480, t0 + 600ms)) << "the refresh interval passed";
    EXPECT_EQ(change.presented(), 6u);
    EXPECT_EQ(change.skipped(), 3u);
}

// Panels that change every frame by themselves (a loading dataset's counters) are presented ten times a second,
// not sixty; at once where the user is at them; a picture that changes, at once whatever its panels.
TEST(FrameChange, PanelsAloneArePresentedTenTimesASecondUnlessTheUserIsAtThem) {
    FrameChange change(500ms, 100ms);
    const auto t0 = std::chrono::steady_clock::now();
    const render::RgbaImage picture = image(64, 48, 7);
    EXPECT_TRUE(change.present(picture, 1, 640, 480, t0, false));
    int presented = 0;
    for (int frame = 1; frame <= 60; ++frame) {  // a second at 60 frames, the counters new each frame
        presented += change.present(picture, 1 + frame, 640, 480, t0 + frame * 1000ms / 60, false);
    }
    EXPECT_GE(presented, 9);
    EXPECT_LE(presented, 11) << "a tenth of a second apart";
    const auto t1 = t0 + 2000ms;
    EXPECT_TRUE(change.present(picture, 100, 640, 480, t1, false));
    EXPECT_TRUE(change.present(picture, 101, 640, 480, t1 + 16ms, true)) << "the user at the panels: at once";
    EXPECT_FALSE(change.present(picture, 102, 640, 480, t1 + 32ms, false)) << "not yet a tenth of a second";
    EXPECT_TRUE(change.present(image(64, 48, 9), 102, 640, 480, t1 + 48ms, false)) << "a new picture: at once";
    EXPECT_FALSE(change.present(image(64, 48, 9), 103, 640, 480, t1 + 64ms, false));
    EXPECT_TRUE(change.present(image(64, 48, 9), 103, 640, 480, t1 + 150ms, false)) << "the panels' change, later";
    EXPECT_FALSE(change.present(image(64, 48, 9), 103, 640, 480, t1 + 300ms, false)) << "nothing changed since";
}

TEST(FrameChange, FingerprintsOfOtherBytesDiffer) {
    const char a[] = "the panels' vertices, 0123456789", b[] = "the panels' vertices, 0123456780";
    EXPECT_EQ(fingerprint(a, sizeof a), fingerprint(a, sizeof a));
    EXPECT_NE(fingerprint(a, sizeof a), fingerprint(b, sizeof b)) << "the last byte of a word";
    EXPECT_NE(fingerprint(a, sizeof a - 1), fingerprint(a, sizeof a)) << "a byte less";
    EXPECT_NE(fingerprint(a, 8), fingerprint(a, 8, fingerprint(b, 8))) << "continued from another seed";
    const char zeros[9] = {};
    EXPECT_NE(fingerprint(zeros, 8), fingerprint(zeros, 9)) << "zeros of other lengths";
}

}  // namespace
}  // namespace lidarscout::viewer
