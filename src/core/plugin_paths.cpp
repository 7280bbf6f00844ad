// The search path of lidarscout's dlopen plugins.
#include "core/plugin_paths.hpp"

#include <cstdlib>
#include <filesystem>

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

}  // namespace lidarscout
