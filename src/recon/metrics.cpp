// Height RMSE and colour PSNR over the texels both images define.
#include "recon/metrics.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace lidarscout::recon {
namespace {

void check_same_shape(const Image& a, const Image& b, int channels) {
    if (a.size != b.size || a.channels != channels || b.channels != channels) {
        throw Error::in_stage("metrics", "images of different shapes");
    }
}

}  // namespace

Score height_rmse_m(const Image& predicted, const Image& truth) {
    check_same_shape(predicted, truth, 1);
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t t = 0; t < truth.values.size(); ++t) {
        const double p = predicted.values[t], q = truth.values[t];
        if (std::isnan(p) || std::isnan(q)) continue;
        sum += (p - q) * (p - q);
        ++n;
    }
    return {n ? std::sqrt(sum / n) : std::numeric_limits<double>::quiet_NaN(), n};
}

Score rgb_psnr_db(const Image& predicted, const Image& truth) {
    check_same_shape(predicted, truth, 3);
    const std::size_t plane = truth.texels();
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t t = 0; t < plane; ++t) {
        bool defined = true;
        for (int c = 0; c < 3; ++c) {
            defined =
                defined && !std::isnan(predicted.values[c * plane + t]) && !std::isnan(truth.values[c * plane + t]);
        }
        if (!defined) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = predicted.values[c * plane + t] - truth.values[c * plane + t];
            sum += d * d;
        }
        ++n;
    }
    if (n == 0) return {std::numeric_limits<double>::quiet_NaN(), 0};
    const double mse = sum / (3.0 * n);
    return {mse > 0 ? std::min(kMaxPsnrDb, 10.0 * std::log10(1.0 / mse)) : kMaxPsnrDb, n};
}

}  // namespace lidarscout::recon
