// Timing helpers shared by the benchmark programs: seconds since a start, medians of runs.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace lidarscout::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace lidarscout::bench
