// Comparing two rendered frames: the PSNR in dB of their RGB channels (peak 255), as the
// viewer's convergence benchmark and tests measure a live frame against a reference frame.
#pragma once

#include "render/resolve.hpp"

namespace lidarscout::render {

inline constexpr double kIdenticalPsnrDb = 100.0;  // reported for identical images (MSE 0)

// Mean squared error over the R, G and B channels of every pixel, as PSNR in dB. Throws
// lidarscout::Error when the sizes differ.
double image_psnr_db(const RgbaImage& image, const RgbaImage& reference);

}  // namespace lidarscout::render
