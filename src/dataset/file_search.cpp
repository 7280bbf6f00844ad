// Recursive search for .las/.laz files.
#include "dataset/file_search.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

namespace lidarscout::dataset {

namespace fs = std::filesystem;

bool has_point_cloud_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".las" || ext == ".laz";
}

namespace {

void search_folder(const fs::path& dir, FoundFiles& out) {
    std::vector<std::string> found;
    std::error_code ec;
    fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        std::error_code fec;
        if (it->is_regular_file(fec) && has_point_cloud_extension(it->path().string())) {
            found.push_back(it->path().string());
        }
    }
    if (ec) out.errors.push_back(dir.string() + ": cannot list folder: " + ec.message());
    std::sort(found.begin(), found.end());
    out.files.insert(out.files.end(), found.begin(), found.end());
}

}  // namespace

FoundFiles find_point_cloud_files(const std::vector<std::string>& paths) {
    FoundFiles out;
    for (const auto& p : paths) {
        std::error_code ec;
        auto st = fs::status(p, ec);
        if (ec || !fs::exists(st)) {
            out.errors.push_back(p + ": no such file or folder");
        } else if (fs::is_directory(st)) {
            search_folder(p, out);
        } else {
            out.files.push_back(p);
        }
    }
    return out;
}

}  // namespace lidarscout::dataset
