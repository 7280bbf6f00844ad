// The CPU-versus-CUDA checks of scripts/gpu_checks.sh as one small program (linked with the
// render and core stages only, so that it travels to a GPU machine with few libraries): every
// case of tests/render/gpu_cases.hpp (every colour mode, EDL, point filters, the bare-earth tint,
// adaptive point sizes over a real spacing, the heightmap pass, data kept on the GPU) drawn on
// the CPU and, where the CUDA plugin opens a GPU, on the GPU; one line per case and a JSON summary.
// Where the GPU side cannot run, the plugin must say why in one line (a plugin that is there must
// have been opened: its reason is then about the device, not about finding it).
// Usage: gpu_harness [--json FILE] [--cpu-only] [--cases NAME,NAME] [--images DIR]
//   --cpu-only: the CPU side only (the plugin is still opened and reported);
//   --images: each case's CPU and GPU images as DIR/NAME_cpu.ppm and DIR/NAME_gpu.ppm.
// Exit status 0 when every side that ran passed and the plugin's report is clean, 1 otherwise.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "render/backend.hpp"
#include "render/cuda_plugin.hpp"
#include "render/gpu_cases.hpp"

using namespace lidarscout;
using namespace lidarscout::render;
using nlohmann::json;

namespace {

struct Options {
    std::string json_path, images;
    bool cpu_only = false;
    std::vector<std::string> cases;  // empty: all
};

std::vector<std::string> split(std::string_view list) {
    std::vector<std::string> out;
    for (std::size_t start = 0; start <= list.size();) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        if (comma > start) out.emplace_back(list.substr(start, comma - start));
        start = comma + 1;
    }
    return out;
}

Options parse_options(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--cpu-only") {
            o.cpu_only = true;
            continue;
        }
        const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
        if (!value) throw Error("gpu_harness: " + std::string(arg) + " needs a value");
        if (arg == "--json") {
            o.json_path = value;
        } else if (arg == "--images") {
            o.images = value;
        } else if (arg == "--cases") {
            o.cases = split(value);
            for (const std::string& name : o.cases) gpu_cases::find_case(name);  // throws on an unknown one
        } else {
            throw Error("gpu_harness: unknown option " + std::string(arg) +
                        " (known: --json --cpu-only --cases --images)");
        }
        ++i;
    }
    return o;
}

// The plugin's report: where it was found, the device or why there is none, and whether that is
// clean (one line; a plugin file that is there was opened, so its reason is not "not found").
json plugin_report() {
    std::string found;
    for (const std::string& path : cuda::plugin_candidates()) {
        if (std::filesystem::exists(path)) {
            found = path;
            break;
        }
    }
    const std::string reason = cuda_unavailable_reason();
    const bool one_line = reason.find('\n') == std::string::npos;
    const bool opened = found.empty() || reason.find("was not built") == std::string::npos;
    return {{"path", found.empty() ? json() : json(found)},
            {"device", cuda_device_name()},
            {"unavailable", reason},
            {"clean", one_line && opened}};
}

std::string percent(double share) { return fmt::format("{:.2f}%", 100.0 * share); }

json cpu_json(const gpu_cases::CpuSide& cpu) {
    json j = {{"status", cpu.failure.empty() ? "passed" : "failed"},
              {"drawn_share", cpu.drawn_share},
              {"drawn_pixels", cpu.frame.drawn_pixels}};
    if (cpu.control_changed_share >= 0) j["control_changed_share"] = cpu.control_changed_share;
    if (!cpu.failure.empty()) j["failure"] = cpu.failure;
    return j;
}

std::string cpu_line(const gpu_cases::CpuSide& cpu) {
    const std::string control =
        cpu.control_changed_share >= 0 ? ", control changes " + percent(cpu.control_changed_share) : "";
    return (cpu.failure.empty() ? "passed" : "FAILED: " + cpu.failure) + " (" + percent(cpu.drawn_share) + " drawn" +
           control + ")";
}

json gpu_json(const gpu_cases::Case& c, const gpu_cases::GpuSide& gpu) {
    json j = {{"status", gpu.failure.empty() ? "passed" : "failed"},
              {"close_share", gpu.close_share},
              {"psnr_db", gpu.psnr_db},
              {"drawn_pixels", gpu.drawn_pixels}};
    if (c.kept_frames > 0) j["kept_frames_equal"] = gpu.kept_frames_equal;
    if (!gpu.failure.empty()) j["failure"] = gpu.failure;
    return j;
}

std::string gpu_line(const gpu_cases::GpuSide& gpu) {
    return (gpu.failure.empty() ? "passed" : "FAILED: " + gpu.failure) +
           fmt::format(" ({} within {} levels, PSNR {:.1f} dB, {} px drawn)", percent(gpu.close_share),
                       gpu_cases::kMaxLevelDifference, gpu.psnr_db, gpu.drawn_pixels);
}

// One case, both sides; the GPU side only when `gpu_note` is empty (else it says why not).
json run_case(const gpu_cases::Case& c, const std::string& gpu_note, const Options& o, ThreadPool& pool,
              bool& passed) {
    json j = {{"name", c.name}, {"checks", c.checks}};
    std::string cpu_text, gpu_text = gpu_note;
    try {
        const gpu_cases::CpuSide cpu = gpu_cases::draw_on_cpu(c, pool);
        j["cpu"] = cpu_json(cpu);
        cpu_text = cpu_line(cpu);
        passed = passed && cpu.failure.empty();
        if (!o.images.empty()) gpu_cases::write_ppm(o.images + "/" + std::string(c.name) + "_cpu.ppm", cpu.frame.image);
        if (gpu_note.empty()) {
            const gpu_cases::GpuSide gpu = gpu_cases::draw_on_gpu(c, cpu, pool);
            j["gpu"] = gpu_json(c, gpu);
            gpu_text = gpu_line(gpu);
            if (!o.images.empty()) gpu_cases::write_ppm(o.images + "/" + std::string(c.name) + "_gpu.ppm", gpu.image);
            passed = passed && gpu.failure.empty();
        } else {
            j["gpu"] = {{"status", "not run"}, {"reason", gpu_note}};
        }
    } catch (const Error& e) {  // a side that throws has failed; the other cases still run
        passed = false;
        (j.contains("cpu") ? j["gpu"] : j["cpu"]) = {{"status", "failed"}, {"failure", e.what()}};
        (cpu_text.empty() ? cpu_text : gpu_text) = std::string("FAILED: ") + e.what();
    }
    fmt::print("{:<23} cpu {}\n{:<23} gpu {}\n", c.name, cpu_text, "", gpu_text);
    std::fflush(stdout);
    return j;
}

void write_json(const std::string& path, const json& j) {
    const std::string part = path + ".part";
    {
        std::ofstream out(part);
        out << j.dump(1) << '\n';
        if (!out) throw Error(part + ": could not be written");
    }
    std::filesystem::rename(part, path);
}

int run(const Options& o) {
    const json plugin = plugin_report();
    const std::string reason = plugin["unavailable"];
    std::string gpu_note;
    if (!reason.empty()) gpu_note = "not run: no device";
    else if (o.cpu_only) gpu_note = "not run: --cpu-only";
    const std::string path = plugin["path"].is_null() ? "not found" : plugin["path"].get<std::string>();
    fmt::print("gpu_harness: plugin {}; {}\n", path,
               reason.empty() ? "device " + plugin["device"].get<std::string>() : "unavailable: " + reason);
    bool passed = plugin["clean"].get<bool>();
    if (!passed) fmt::print("gpu_harness: FAILED: the plugin is there but was not opened, or said why in lines\n");
    ThreadPool pool(std::max(2u, std::thread::hardware_concurrency()));
    json cases = json::array();
    for (const gpu_cases::Case& c : gpu_cases::cases()) {
        if (!o.cases.empty() && std::find(o.cases.begin(), o.cases.end(), c.name) == o.cases.end()) continue;
        cases.push_back(run_case(c, gpu_note, o, pool, passed));
    }
    const std::string gpu_side = gpu_note.empty() ? "run" : reason.empty() ? gpu_note : gpu_note + " (" + reason + ")";
    const json summary = {{"plugin", plugin},
                          {"gpu_side", gpu_side},
                          {"tolerance",
                           {{"max_level_difference", gpu_cases::kMaxLevelDifference},
                            {"min_close_share", gpu_cases::kMinCloseShare},
                            {"max_drawn_difference_share", gpu_cases::kMaxDrawnDifferenceShare},
                            {"min_control_changed_share", gpu_cases::kMinControlChangedShare}}},
                          {"cases", cases},
                          {"passed", passed}};
    if (!o.json_path.empty()) write_json(o.json_path, summary);
    fmt::print("gpu_harness: {} cases, {}\n", cases.size(), passed ? "passed" : "FAILED");
    return passed ? 0 : 1;
}

}  // namespace

constexpr const char* kUsage = "[--json FILE] [--cpu-only] [--cases NAME,NAME] [--images DIR]";

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("gpu_harness", kUsage, argc, argv,
                                         [](int argc, char** argv) { return run(parse_options(argc, argv)); });
}
