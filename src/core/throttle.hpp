// Throttling work that every change makes due but that may wait a little: re-sorting a long
// queue when the camera moves. Small queues are worked on at once; long ones at most once per
// interval, so that a camera moving every frame does not hold a lock for a sort each frame.
#pragma once

#include <chrono>
#include <cstddef>

namespace lidarscout {

class Throttle {
public:
    using Clock = std::chrono::steady_clock;

    Throttle(std::chrono::milliseconds interval, std::size_t small) : interval_(interval), small_(small) {}

    // True when work on `size` items may run now: a small size, or the interval has passed
    // since the last done().
    bool due(std::size_t size, Clock::time_point now = Clock::now()) const {
        return size <= small_ || now - last_ >= interval_;
    }
    void done(Clock::time_point now = Clock::now()) { last_ = now; }

private:
    std::chrono::milliseconds interval_;
    std::size_t small_;
    Clock::time_point last_{};
};

}  // namespace lidarscout
