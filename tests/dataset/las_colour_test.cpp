// LAS colour to 8 bits: 16-bit channels give their high byte, 8-bit ones stay as they are.
#include "dataset/las_colour.hpp"

#include <gtest/gtest.h>

namespace lidarscout::dataset {
namespace {

TEST(LasColour, RgbFromLas) {
    EXPECT_EQ(rgb8_from_las(65535, 0, 128), (Rgb8{255, 0, 0}));
    EXPECT_EQ(rgb8_from_las(256, 511, 0x1234), (Rgb8{1, 1, 0x12}));
    EXPECT_EQ(rgb8_from_las(200, 100, 255), (Rgb8{200, 100, 255}));
}

}  // namespace
}  // namespace lidarscout::dataset
