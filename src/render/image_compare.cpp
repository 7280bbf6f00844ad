// PSNR of two rendered frames.
#include "render/image_compare.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace lidarscout::render {

double image_psnr_db(const RgbaImage& image, const RgbaImage& reference) {
    if (image.width != reference.width || image.height != reference.height ||
        image.pixels.size() != reference.pixels.size()) {
        throw Error("image_psnr_db: " + std::to_string(image.width) + "x" + std::to_string(image.height) + " against " +
                    std::to_string(reference.width) + "x" + std::to_string(reference.height));
    }
    double sum = 0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const std::uint32_t a = image.pixels[i], b = reference.pixels[i];
        for (int shift = 0; shift < 24; shift += 8) {
            const double d = static_cast<double>((a >> shift) & 0xff) - static_cast<double>((b >> shift) & 0xff);
            sum += d * d;
        }
    }
    if (image.pixels.empty() || sum == 0) return kIdenticalPsnrDb;
    const double mse = sum / (3.0 * static_cast<double>(image.pixels.size()));
    return 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace lidarscout::render
