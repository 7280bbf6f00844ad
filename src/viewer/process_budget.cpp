// The process's budget split between what the program holds and the scheduler's data.
//
// kNetworkBytes: `view ky-jmo335 --memory 128M --quit-after 20` under Xvfb peaked at 446 MB with the
// network and 301 MB with --no-cnn; the resident file pages alone went from 100 to 179 MB.
#include "viewer/process_budget.hpp"

#include <algorithm>
#include <cstdio>

namespace lidarscout::viewer {
namespace {

std::uint64_t mib(std::uint64_t bytes) { return (bytes + (1u << 19)) >> 20; }

// The network fits when the budget holds what the program needs with it and the least data.
bool network_fits(std::uint64_t asked, std::uint64_t at_start) {
    return asked >= at_start + kNetworkBytes + kLeastDataBytes;
}

}  // namespace

std::string network_declined_note(std::size_t tiles) {
    return "the overview of " + std::to_string(tiles) + " tiles leaves no room for the heightmap network: linear "
           "heightmaps only (a larger --memory gives it)";
}

bool overview_fills(std::uint64_t overview, std::uint64_t data) { return overview * 10 >= data * 9; }

std::string overview_fills_note(std::uint64_t overview, std::uint64_t data, std::size_t tiles) {
    if (!overview_fills(overview, data)) return "";  // under 90%: room for full resolution
    char line[300];
    std::snprintf(line, sizeof line,
                  "the overview of %zu tiles (chunk points, patches, nearest heightmaps) holds %llu MiB of the "
                  "%llu MiB left for data: little or no room for full-resolution points (a larger --memory gives it)",
                  tiles, static_cast<unsigned long long>(mib(overview)), static_cast<unsigned long long>(mib(data)));
    return line;
}

ProcessBudget::ProcessBudget(std::uint64_t asked, std::uint64_t outside_at_start, bool network)
    : asked_(asked), asked_at_start_(asked), at_start_(outside_at_start), network_wanted_(network),
      network_(network && network_fits(asked, outside_at_start)) {}

void ProcessBudget::observe(std::uint64_t resident, std::uint64_t ledger_used) {
    if (resident > ledger_used) seen_ = std::max(seen_, resident - ledger_used);
}

std::uint64_t ProcessBudget::outside() const {
    return std::max(seen_, at_start_ + (network_ ? kNetworkBytes : 0));
}

bool ProcessBudget::network_leaves_room(std::uint64_t overview) const {
    const std::uint64_t held = std::max(seen_, at_start_) + kNetworkBytes;
    return asked_ > held && !overview_fills(overview, asked_ - held);
}

ProcessBudgetPlan ProcessBudget::plan() const {
    ProcessBudgetPlan p;
    p.network = network_;
    const std::uint64_t held = outside(), least = held + kLeastDataBytes;
    p.data = asked_ >= least ? asked_ - held : kLeastDataBytes;
    const auto n = [](std::uint64_t bytes) { return static_cast<unsigned long long>(mib(bytes)); };
    char line[400];
    if (asked_ < least) {
        std::snprintf(line, sizeof line,
                      "memory budget %llu MiB is below the %llu MiB the viewer needs to run (%llu MiB for the "
                      "program, its libraries, window and threads, %llu MiB for data): running with %llu MiB%s",
                      n(asked_), n(least), n(held), n(kLeastDataBytes), n(least),
                      network_wanted_ && !network_ ? ", linear heightmaps only" : "");
        p.note = line;
        p.below = true;
    } else if (network_wanted_ && !network_ && !declined_) {
        std::snprintf(line, sizeof line,
                      "the memory budget at start (%llu MiB) left no room for the heightmap network (%llu MiB with "
                      "its libraries): linear heightmaps only", n(asked_at_start_), n(kNetworkBytes));
        p.note = line;
    }
    return p;
}

}  // namespace lidarscout::viewer
