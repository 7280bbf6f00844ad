// The output check (POSIX stat/access): inputs by device and inode, folders by canonical path.
#include "io/output_check.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "net/url.hpp"

namespace lidarscout::io {
namespace fs = std::filesystem;

namespace {

using FileId = std::pair<dev_t, ino_t>;

struct Input {
    std::string path;   // as the user (or a list) named it
    FileId id{};
    bool folder = false;
    fs::path canonical;  // symbolic links resolved
};

std::optional<Input> stat_input(const std::string& path) {
    struct stat st {};
    if (path.empty() || net::is_url(path) || ::stat(path.c_str(), &st) != 0) return std::nullopt;
    std::error_code ec;
    Input in{path, {st.st_dev, st.st_ino}, S_ISDIR(st.st_mode), fs::canonical(path, ec)};
    if (ec) in.canonical = fs::absolute(path, ec);
    return in;
}

std::vector<Input> stat_inputs(const std::vector<std::string>& paths) {
    std::vector<Input> out;
    for (const auto& p : paths) {
        if (auto in = stat_input(p)) out.push_back(std::move(*in));
    }
    return out;
}

std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

std::vector<std::string_view> extensions_of(OutputKind kind) {
    switch (kind) {
        case OutputKind::GeoTiff: return {".tif", ".tiff"};
        case OutputKind::Png: return {".png"};
        case OutputKind::Hillshade: return {".tif", ".tiff", ".png"};
        case OutputKind::GeoPackage: return {".gpkg"};
        case OutputKind::Json: return {".json"};
        case OutputKind::Catalog: return {".vpc"};
        case OutputKind::PointCloud: return {".las", ".laz"};
        case OutputKind::Profile: return {".csv", ".las", ".laz", ".png"};
        case OutputKind::TrainingData:
        case OutputKind::Folder: return {};
    }
    return {};
}

// Extensions of the formats lidarscout reads or writes: what a training-data file may not end in.
constexpr std::array<std::string_view, 9> kKnownFormats = {".las", ".laz", ".tif", ".tiff", ".png",
                                                           ".json", ".vpc", ".txt", ".csv"};

bool is_point_cloud_name(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".las" || ext == ".laz";
}

// `inner` is `outer` or lies below it (both canonical).
bool lies_in(const fs::path& inner, const fs::path& outer) {
    auto o = outer.begin(), i = inner.begin();
    for (; o != outer.end(); ++o, ++i) {
        if (i == inner.end() || *i != *o) return false;
    }
    return true;
}

[[noreturn]] void refuse(const OutputTarget& out, const std::string& cause) {
    throw Error(out.path, std::nullopt, "refusing the output of " + out.option + ": " + cause);
}

void check_extension(const OutputTarget& out) {
    if (out.kind == OutputKind::Folder) return;
    const std::string ext = lower_extension(out.path);
    if (out.kind == OutputKind::TrainingData) {
        if (std::find(kKnownFormats.begin(), kKnownFormats.end(), ext) != kKnownFormats.end()) {
            refuse(out, "training samples are lidarscout's own layout, not a " + ext +
                            " file; choose another extension (e.g. .bin)");
        }
        return;
    }
    const auto wanted = extensions_of(out.kind);
    if (std::find(wanted.begin(), wanted.end(), ext) == wanted.end()) {
        refuse(out, "it must end in " + expected_extensions(out.kind) + " (" +
                        (ext.empty() ? std::string("no extension") : ext) + " given)");
    }
}

// An existing output: not a folder (unless one is wanted), not an input file or folder.
void check_existing(const OutputTarget& out, const std::vector<Input>& inputs) {
    struct stat st {};
    if (::stat(out.path.c_str(), &st) != 0) return;
    const bool folder = S_ISDIR(st.st_mode);
    if (folder && out.kind != OutputKind::Folder) refuse(out, "it is a folder; name a file in it");
    if (!folder && out.kind == OutputKind::Folder) refuse(out, "it is a file, not a folder");
    for (const auto& in : inputs) {
        if (in.id == FileId{st.st_dev, st.st_ino}) {
            refuse(out, "it is the input " + in.path + (in.folder ? " (the same folder)" : " (the same file)") +
                            "; the input is left untouched, choose another name");
        }
    }
}

// An output inside an input folder: a tile name would add it to the inputs; an output folder
// there (or one that holds an input file) would put its files among the user's.
void check_input_folders(const OutputTarget& out, const std::vector<Input>& inputs) {
    std::error_code ec;
    const fs::path where = fs::weakly_canonical(fs::absolute(out.path, ec), ec);
    if (ec) return;
    for (const auto& in : inputs) {
        if (out.kind == OutputKind::Folder && !in.folder && lies_in(in.canonical, where)) {
            refuse(out, "it holds the input " + in.path + "; its files would land among the inputs, write it "
                        "elsewhere");
        }
        if (!in.folder || !lies_in(where, in.canonical)) continue;
        if (out.kind == OutputKind::Folder) {
            refuse(out, "it lies inside the input folder " + in.path + "; write it elsewhere");
        }
        if (!is_point_cloud_name(out.path)) continue;
        std::error_code exists_ec;
        if (fs::exists(out.path, exists_ec)) {
            refuse(out, "it is a tile of the input folder " + in.path +
                            " (an input file); the input is left untouched, choose another name");
        }
        refuse(out, "it lies inside the input folder " + in.path +
                        " with a tile's name, so it would become one of the inputs; write it elsewhere");
    }
}

// The folder the output goes into exists, is a folder and is writable (for a folder output: its
// nearest existing ancestor, since missing folders are created).
void check_folder(const OutputTarget& out) {
    fs::path dir = fs::path(out.path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (out.kind == OutputKind::Folder) {
        dir = fs::absolute(out.path, ec);
        while (!fs::exists(dir, ec) && dir.has_parent_path() && dir != dir.parent_path()) dir = dir.parent_path();
    }
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0) refuse(out, "its folder " + dir.string() + " does not exist");
    if (!S_ISDIR(st.st_mode)) refuse(out, dir.string() + " is a file, not a folder");
    if (::access(dir.c_str(), W_OK | X_OK) != 0) refuse(out, "its folder " + dir.string() + " is not writable");
}

// Two outputs of one command naming the same file.
void check_distinct(const std::vector<OutputTarget>& outputs) {
    std::vector<std::pair<fs::path, const OutputTarget*>> seen;
    for (const auto& out : outputs) {
        std::error_code ec;
        const fs::path where = fs::weakly_canonical(fs::absolute(out.path, ec), ec);
        for (const auto& [path, other] : seen) {
            if (path == where) refuse(out, "it is also the output of " + other->option + "; give each its own name");
        }
        seen.emplace_back(where, &out);
    }
}

std::mutex g_protected_mutex;
std::set<FileId> g_protected;

}  // namespace

std::string expected_extensions(OutputKind kind) {
    const auto wanted = extensions_of(kind);
    if (wanted.size() == 1) return std::string(wanted[0]);
    std::string text = "one of";
    for (std::size_t i = 0; i < wanted.size(); ++i) text += (i ? ", " : " ") + std::string(wanted[i]);
    return text;
}

void check_outputs(const std::vector<OutputTarget>& outputs, const std::vector<std::string>& inputs) {
    const std::vector<Input> in = stat_inputs(inputs);
    std::vector<OutputTarget> named;
    for (const auto& out : outputs) {
        if (!out.path.empty()) named.push_back(out);
    }
    for (const auto& out : named) {
        check_existing(out, in);
        check_input_folders(out, in);
    }
    check_distinct(named);
    for (const auto& out : named) {
        check_extension(out);
        check_folder(out);
    }
}

void protect_inputs(const std::vector<std::string>& inputs) {
    const std::vector<Input> in = stat_inputs(inputs);
    const std::lock_guard lock(g_protected_mutex);
    for (const auto& i : in) {
        if (!i.folder) g_protected.insert(i.id);
    }
}

void forget_protected_inputs() {
    const std::lock_guard lock(g_protected_mutex);
    g_protected.clear();
}

void refuse_protected_input(const std::string& target) {
    struct stat st {};
    if (::stat(target.c_str(), &st) != 0) return;
    const std::lock_guard lock(g_protected_mutex);
    if (g_protected.count({st.st_dev, st.st_ino})) {
        throw Error(target, std::nullopt, "refusing to overwrite an input file of this command");
    }
}

}  // namespace lidarscout::io
