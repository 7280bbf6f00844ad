// The table of temporary files and the signal handler that removes them.
#include "io/temporary_files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <thread>

namespace lidarscout::io {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
std::array<std::atomic<const char*>, 64> table{};

// Who has the signals: nobody (kFree), a handler that is removing the files and ending the
// process (kEnding), or a SignalHold (kHeld), which raises `held` again when it ends.
enum State : int { kFree, kEnding, kHeld };
std::atomic<int> state{kFree};
std::atomic<int> held{0};
static_assert(std::atomic<int>::is_always_lock_free, "used in a signal handler");

[[noreturn]] void wait_for_the_end() {
    for (;;) ::pause();  // the thread that took kEnding ends the process
}

void on_signal(int signal) {
    int expected = kFree;
    if (!state.compare_exchange_strong(expected, kEnding)) {
        if (expected == kEnding) wait_for_the_end();
        held.store(signal);  // kHeld: the hold raises it again when it ends
        return;
    }
    for (auto& entry : table) {
        if (const char* path = entry.load()) ::unlink(path);
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

void remove_temporary_files_on_signal() {
    for (const int s : kSignals) {
        struct sigaction action {};
        action.sa_handler = on_signal;
        sigemptyset(&action.sa_mask);
        ::sigaction(s, &action, nullptr);
    }
}

TemporaryFileGuard::TemporaryFileGuard(const std::string& path) {
    for (int i = 0; i < static_cast<int>(table.size()); ++i) {
        const char* empty = nullptr;
        if (table[i].compare_exchange_strong(empty, path.c_str())) {
            slot_ = i;
            return;
        }
    }
}

TemporaryFileGuard::~TemporaryFileGuard() {
    if (slot_ >= 0) table[slot_].store(nullptr);
}

SignalHold::SignalHold() {
    for (int expected = kFree; !state.compare_exchange_weak(expected, kHeld); expected = kFree) {
        if (expected == kEnding) wait_for_the_end();
        std::this_thread::yield();  // another hold, or a spurious failure
    }
}

SignalHold::~SignalHold() {
    state.store(kFree);
    if (const int signal = held.exchange(0)) std::raise(signal);  // the handler runs now, in this thread
}

}  // namespace lidarscout::io
