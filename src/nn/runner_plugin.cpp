// Opening the LibTorch runner plugin with dlopen (see runner_plugin.hpp).
#include "nn/runner_plugin.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/error.hpp"

#ifndef LIDARSCOUT_BUILD_DIR
#define LIDARSCOUT_BUILD_DIR ""
#endif

namespace lidarscout::nn {
namespace fs = std::filesystem;

std::string executable_dir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : exe.parent_path().string();
}

std::vector<std::string> runner_candidates() {
    std::vector<std::string> out;
    if (const char* env = std::getenv("LIDARSCOUT_TORCH_RUNNER"); env && *env) out.emplace_back(env);
    if (const std::string dir = executable_dir(); !dir.empty()) {
        out.push_back((fs::path(dir) / kRunnerFileName).string());
        out.push_back((fs::path(dir) / ".." / "lib" / "lidarscout" / kRunnerFileName).lexically_normal().string());
    }
    if (*LIDARSCOUT_BUILD_DIR) out.push_back((fs::path(LIDARSCOUT_BUILD_DIR) / kRunnerFileName).string());
    return out;
}

namespace {

const LidarscoutRunnerApi* open_runner() {
    std::string tried;
    for (const auto& path : runner_candidates()) {
        if (!fs::exists(path)) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) throw Error(path, std::nullopt, std::string("cannot open the LibTorch runner: ") + dlerror());
        using Entry = const LidarscoutRunnerApi* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, "lidarscout_runner_api"));
        const LidarscoutRunnerApi* api = entry ? entry() : nullptr;
        if (!api || api->abi != LIDARSCOUT_RUNNER_ABI) {
            throw Error(path, std::nullopt, "not a LibTorch runner of this lidarscout version (interface mismatch)");
        }
        return api;  // never closed: LibTorch does not unload cleanly
    }
    throw Error("the heightmap network needs " + std::string(kRunnerFileName) +
                " (built with lidarscout; set LIDARSCOUT_TORCH_RUNNER to its path); looked in: " + tried);
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
