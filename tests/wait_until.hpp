// Waiting in tests for background work: a predicate polled until it holds or a timeout passes.
#pragma once

#include <chrono>
#include <thread>

namespace lidarscout::test {

// Polls `pred` every 5 ms; false when it still does not hold after `timeout`.
template <typename Pred>
bool wait_until(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(120)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!pred()) {
        if (std::chrono::steady_clock::now() > end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

}  // namespace lidarscout::test
