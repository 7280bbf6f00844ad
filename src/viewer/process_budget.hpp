// The viewer's memory budget as the whole process's: what the program holds outside the scheduler's
// ledger (its libraries' code and data, the window's OpenGL context, the heightmap network, threads'
// stacks, the allocator's slack) is taken off the budget the user gives before the scheduler gets
// the rest for data; below what the viewer needs to run it says so in one line and runs with the
// least that works. Decisions only, no measuring (the window loop measures: viewer/app), so that
// they can be tested on their own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace lidarscout::viewer {

// The least the scheduler works with: a small dataset's chunk points and heightmaps and a tile or
// two at full resolution.
inline constexpr std::uint64_t kLeastDataBytes = 32ull << 20;
// What the heightmap network adds to the resident size once it has run (Debian 12's LibTorch 1.13:
// libtorch_cpu, oneDNN and their libraries' pages, its allocator, the model), measured on
// ky-jmo335 with and without --no-cnn (doc in process_budget.cpp).
inline constexpr std::uint64_t kNetworkBytes = 150ull << 20;

struct ProcessBudgetPlan {
    std::uint64_t data = 0;  // the scheduler's budget (never 0, which would mean its default)
    bool network = true;     // the heightmap network fits (decided once, at start)
    std::string note;        // one line when the budget is below what the viewer needs (or leaves out
                             // the network); empty else
    bool below = false;      // the note says the budget is below what the viewer needs
};

// One line when the overview (every tile's chunk points, the patch table and the nearest heightmaps:
// what the scheduler holds whatever the budget) fills most of the data's share, so that full
// resolution has little room or none; empty else. `overview` and `data` in bytes.
std::string overview_fills_note(std::uint64_t overview, std::uint64_t data, std::size_t tiles);
// The line saying the network was left out for the overview of `tiles` tiles (ProcessBudget::network_leaves_room).
std::string network_declined_note(std::size_t tiles);
// Whether the overview holds 90% of the data's share or more (what overview_fills_note says).
bool overview_fills(std::uint64_t overview, std::uint64_t data);

class ProcessBudget {
public:
    // `asked`: the user's budget for the whole process; `outside_at_start`: what the process holds
    // with its window up and no dataset; `network`: the heightmap network is wanted.
    ProcessBudget(std::uint64_t asked, std::uint64_t outside_at_start, bool network);

    void set_asked(std::uint64_t bytes) { asked_ = bytes; }
    std::uint64_t asked() const { return asked_; }
    // Notes what the process holds now beyond the scheduler's ledger; the most seen is what counts
    // (the program may hold it again).
    void observe(std::uint64_t resident, std::uint64_t ledger_used);
    // The dataset's opening is over (its catalog's blocks, its sidecar's buffers are gone): what was seen
    // before is forgotten, so that they do not keep the data's share small for the rest of the run.
    void opening_over() { seen_ = 0; }
    // What the program holds outside the data: the most seen, or what it held at start and the
    // network's share, if more.
    std::uint64_t outside() const;
    ProcessBudgetPlan plan() const;
    // Whether, with the network loaded (kNetworkBytes more beside what is held now), an overview of
    // `overview` bytes (SchedulerStats::overview_core_bytes) would still leave full resolution room.
    bool network_leaves_room(std::uint64_t overview) const;
    // The scheduler left the network out after all (SchedulerStats::network_declined; its note says why).
    void network_declined() { network_ = false, declined_ = true; }
    bool declined() const { return declined_; }

private:
    std::uint64_t asked_, asked_at_start_, at_start_, seen_ = 0;
    bool network_wanted_, network_, declined_ = false;
};

}  // namespace lidarscout::viewer
