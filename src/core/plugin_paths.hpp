// Where lidarscout's optional plugins (the LibTorch runner, the CUDA rasterizer) are looked
// for: the path in an environment variable, next to the program, in ../lib/lidarscout from
// it, and in the build tree the program was built in; and opening the first one found.
#pragma once

#include <string>
#include <vector>

namespace lidarscout {

// The folder of the running executable (empty when it cannot be told).
std::string executable_dir();

// Candidate paths of plugin `file_name`, in the order above; `env_var` names the override,
// `build_dir` is the build tree ("" for none).
std::vector<std::string> plugin_candidates(const char* env_var, const std::string& file_name,
                                           const std::string& build_dir);

struct PluginEntry {
    std::string path;      // the file opened; empty when no candidate exists
    void* entry = nullptr;  // its symbol `entry`
};

// Opens the first of `candidates` that exists with dlopen (never closed: the plugins' runtimes
// do not unload cleanly) and returns its symbol `entry`; `before_dlopen`, when given, runs
// just before. Throws lidarscout::Error "PATH: cannot open the <what>: ..." or "PATH: not a
// <what> of this lidarscout version" when the file cannot be opened or lacks the symbol. When
// no candidate exists, returns an empty PluginEntry and lists the paths looked at in `tried`.
PluginEntry open_plugin_entry(const std::vector<std::string>& candidates, const char* entry, const std::string& what,
                              std::string& tried, void (*before_dlopen)() = nullptr);

}  // namespace lidarscout
