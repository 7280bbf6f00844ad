// Pull-push hole filling (see hole_fill.hpp): each coarser level averages the defined texels
// below it (weights capped at 1), then each level pushes its values into the partly defined
// texels of the finer one, bilinearly.
#include "recon/hole_fill.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lidarscout::recon {
namespace {

// One level of the pull-push pyramid: values and their weights (0..1).
struct PyramidLevel {
    int size = 0;
    std::vector<float> value, weight;
};

PyramidLevel pulled(const PyramidLevel& fine) {
    PyramidLevel c;
    c.size = (fine.size + 1) / 2;
    c.value.assign(static_cast<std::size_t>(c.size) * c.size, 0.0f);
    c.weight.assign(c.value.size(), 0.0f);
    for (int j = 0; j < fine.size; ++j) {
        for (int i = 0; i < fine.size; ++i) {
            const std::size_t f = static_cast<std::size_t>(j) * fine.size + i;
            const std::size_t p = static_cast<std::size_t>(j / 2) * c.size + i / 2;
            c.value[p] += fine.weight[f] * fine.value[f];
            c.weight[p] += fine.weight[f];
        }
    }
    for (std::size_t p = 0; p < c.value.size(); ++p) {
        if (c.weight[p] > 0.0f) c.value[p] /= c.weight[p];
        c.weight[p] = std::min(c.weight[p], 1.0f);
    }
    return c;
}

// The coarse level's value at the centre of fine texel (i, j).
float upsampled(const PyramidLevel& coarse, int i, int j) {
    return sample_bilinear(coarse.value, coarse.size, (i + 0.5) / 2.0, (j + 0.5) / 2.0);
}

void pushed(PyramidLevel& fine, const PyramidLevel& coarse) {
    for (int j = 0; j < fine.size; ++j) {
        for (int i = 0; i < fine.size; ++i) {
            const std::size_t f = static_cast<std::size_t>(j) * fine.size + i;
            const float w = fine.weight[f];
            if (w >= 1.0f) continue;
            fine.value[f] = w * fine.value[f] + (1.0f - w) * upsampled(coarse, i, j);
        }
    }
}

}  // namespace

bool hole_fill(std::vector<float>& heights, int size, const std::vector<bool>& wanted) {
    std::vector<PyramidLevel> levels(1);
    levels[0].size = size;
    levels[0].value.resize(heights.size());
    levels[0].weight.resize(heights.size());
    bool any = false;
    for (std::size_t t = 0; t < heights.size(); ++t) {
        const bool defined = !std::isnan(heights[t]);
        levels[0].value[t] = defined ? heights[t] : 0.0f;
        levels[0].weight[t] = defined ? 1.0f : 0.0f;
        any = any || defined;
    }
    if (!any) return false;
    while (levels.back().size > 1) levels.push_back(pulled(levels.back()));
    for (std::size_t k = levels.size() - 1; k-- > 0;) pushed(levels[k], levels[k + 1]);
    for (std::size_t t = 0; t < heights.size(); ++t) {
        if (wanted[t] && std::isnan(heights[t])) heights[t] = levels[0].value[t];
    }
    return true;
}

float sample_bilinear(const std::vector<float>& raster, int size, double u, double v) {
    const auto axis = [&](double t, int& k0, double& f) {
        const double c = std::clamp(t - 0.5, 0.0, static_cast<double>(size - 1));
        k0 = std::min(static_cast<int>(c), std::max(size - 2, 0));
        f = c - k0;
    };
    int i0 = 0, j0 = 0;
    double fu = 0, fv = 0;
    axis(u, i0, fu), axis(v, j0, fv);
    const int i1 = std::min(i0 + 1, size - 1), j1 = std::min(j0 + 1, size - 1);
    const auto at = [&](int a, int b) { return raster[static_cast<std::size_t>(b) * size + a]; };
    const double bottom = (1 - fu) * at(i0, j0) + fu * at(i1, j0), top = (1 - fu) * at(i0, j1) + fu * at(i1, j1);
    return static_cast<float>((1 - fv) * bottom + fv * top);
}

}  // namespace lidarscout::recon
