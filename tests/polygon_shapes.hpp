// Polygon shapes for the polygon tests and bench_polygon: a ring of n vertices around (0, 0) at radii
// r(i), evenly spaced in angle (circles, zigzags, stars).
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>

#include "core/polygon.hpp"

namespace lidarscout::test {

template <typename Radius>
Ring radial_ring(std::size_t n, Radius r) {
    Ring ring(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
        ring[i] = {r(i) * std::cos(a), r(i) * std::sin(a)};
    }
    return ring;
}

}  // namespace lidarscout::test
