// The search path of lidarscout's dlopen plugins, and opening one.
#include "core/plugin_paths.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

#include "core/error.hpp"

namespace lidarscout {
namespace fs = std::filesystem;

std::string executable_dir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : exe.parent_path().string();
}

std::vector<std::string> plugin_candidates(const char* env_var, const std::string& file_name,
                                           const std::string& build_dir) {
    std::vector<std::string> out;
    if (const char* env = std::getenv(env_var); env && *env) out.emplace_back(env);
    if (const std::string dir = executable_dir(); !dir.empty()) {
        out.push_back((fs::path(dir) / file_name).string());
        out.push_back((fs::path(dir) / ".." / "lib" / "lidarscout" / file_name).lexically_normal().string());
    }
    if (!build_dir.empty()) out.push_back((fs::path(build_dir) / file_name).string());
    return out;
}

PluginEntry open_plugin_entry(const std::vector<std::string>& candidates, const char* entry, const std::string& what,
                              std::string& tried, void (*before_dlopen)()) {
    for (const auto& path : candidates) {
        if (!fs::exists(path)) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        if (before_dlopen) before_dlopen();
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) throw Error(path, std::nullopt, "cannot open the " + what + ": " + dlerror());
        void* symbol = dlsym(handle, entry);
        if (!symbol) {
            throw Error(path, std::nullopt, "not a " + what + " of this lidarscout version (no " + entry + ")");
        }
        return {path, symbol};
    }
    return {};
}

}  // namespace lidarscout
