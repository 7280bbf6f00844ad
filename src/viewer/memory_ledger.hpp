// What the viewer holds against its memory budget, in one object the scheduler and the residency
// share instead of asking each other through callbacks: the budget; the scheduler's heightmaps and
// chunk-point sets (kept as they change); the patch grid's chunk points (read from the grid, which
// keeps its own count). The residency adds its own blocks and details when it weighs a load, and
// says what it holds after each step, so that the scheduler can keep its heightmaps within the rest.
// Atomics only: read and written from any thread without a lock, so that no lock order ties the
// scheduler and the residency through it.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/patch_grid.hpp"

namespace lidarscout::viewer {

class MemoryLedger {
public:
    explicit MemoryLedger(std::uint64_t budget, const lidarscout::PatchGrid* grid = nullptr)
        : budget_(budget), grid_(grid) {}

    std::uint64_t budget() const { return budget_.load(std::memory_order_relaxed); }
    void set_budget(std::uint64_t bytes) { budget_.store(bytes, std::memory_order_relaxed); }

    // The scheduler's heightmaps and chunk-point sets.
    void add_patch_bytes(std::int64_t delta) {
        patches_.fetch_add(static_cast<std::uint64_t>(delta), std::memory_order_relaxed);
    }
    std::uint64_t patch_bytes() const { return patches_.load(std::memory_order_relaxed); }
    // Everything held outside the residency: the grid's chunk points and the patches.
    std::uint64_t outside_residency() const { return (grid_ ? grid_->memory_bytes() : 0) + patch_bytes(); }
    // What the residency holds (its blocks, details and the tile it decodes), as it said last.
    void set_residency_bytes(std::uint64_t bytes) { residency_.store(bytes, std::memory_order_relaxed); }
    std::uint64_t residency_bytes() const { return residency_.load(std::memory_order_relaxed); }
    // Everything the ledger counts.
    std::uint64_t used() const { return outside_residency() + residency_bytes(); }

private:
    std::atomic<std::uint64_t> budget_;
    std::atomic<std::uint64_t> patches_{0};
    std::atomic<std::uint64_t> residency_{0};
    const lidarscout::PatchGrid* grid_;
};

}  // namespace lidarscout::viewer
