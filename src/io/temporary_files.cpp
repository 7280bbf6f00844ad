// The table of temporary files and the signal handler that removes them.
#include "io/temporary_files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>

namespace lidarscout::io {
namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
std::array<std::atomic<const char*>, 64> table{};

void on_signal(int signal) {
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

}  // namespace lidarscout::io
