// Opening the LibTorch runner plugin with dlopen (see runner_plugin.hpp).
#include "nn/runner_plugin.hpp"

#include <atomic>
#include <mutex>

#include "core/error.hpp"
#include "core/plugin_paths.hpp"

#ifndef LIDARSCOUT_BUILD_DIR
#define LIDARSCOUT_BUILD_DIR ""
#endif

#if defined(__SANITIZE_ADDRESS__)
#define LIDARSCOUT_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LIDARSCOUT_ASAN 1
#endif
#endif

namespace {
std::atomic<bool> runner_opened{false};
}  // namespace

#ifdef LIDARSCOUT_ASAN
// Sanitizer builds: LeakSanitizer's check at exit stops every thread through a tracer, and
// with LibTorch's OpenMP workers alive it crashes ("Tracer caught signal 11") instead of
// reporting. A process that opened the runner therefore skips the leak check (AddressSanitizer's
// other checks stay on); every other process keeps it.
extern "C" int __lsan_is_turned_off() { return runner_opened.load() ? 1 : 0; }
#endif

namespace lidarscout::nn {

std::vector<std::string> runner_candidates() {
    return plugin_candidates("LIDARSCOUT_TORCH_RUNNER", kRunnerFileName, LIDARSCOUT_BUILD_DIR);
}

namespace {

void mark_runner_opened() { runner_opened = true; }  // LibTorch may start threads while loading

const LidarscoutRunnerApi* open_runner() {
    std::string tried;
    const PluginEntry p = open_plugin_entry(runner_candidates(), "lidarscout_runner_api", "LibTorch runner", tried,
                                            mark_runner_opened);
    if (!p.entry) {
        throw Error("the heightmap network needs " + std::string(kRunnerFileName) +
                    " (built with lidarscout; set LIDARSCOUT_TORCH_RUNNER to its path); looked in: " + tried);
    }
    using Entry = const LidarscoutRunnerApi* (*)();
    const LidarscoutRunnerApi* api = reinterpret_cast<Entry>(p.entry)();
    if (!api || api->abi != LIDARSCOUT_RUNNER_ABI) {
        throw Error(p.path, std::nullopt, "not a LibTorch runner of this lidarscout version (interface mismatch)");
    }
    return api;
}

}  // namespace

const LidarscoutRunnerApi& runner_api() {
    static std::once_flag once;
    static const LidarscoutRunnerApi* api = nullptr;
    static std::string failure;
    std::call_once(once, [] {
        try {
            api = open_runner();
        } catch (const Error& e) {
            failure = e.what();
        }
    });
    if (!api) throw Error(failure);
    return *api;
}

}  // namespace lidarscout::nn
