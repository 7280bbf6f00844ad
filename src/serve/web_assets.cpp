// Reading the page's folder into memory.
#include "serve/web_assets.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "core/plugin_paths.hpp"

#ifndef LIDARSCOUT_SOURCE_DIR
#define LIDARSCOUT_SOURCE_DIR ""
#endif

namespace lidarscout::serve {
namespace fs = std::filesystem;
namespace {

bool plain_name(const std::string& name) {
    if (name.empty() || name.front() == '.') return false;
    for (const char c : name) {
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-')) return false;
    }
    return true;
}

// The content type of a page file by its extension; empty for one not served.
std::string content_type_of(const fs::path& p) {
    const std::string ext = p.extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    return {};
}

std::string read_whole(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::string s{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (!in.good() && !in.eof()) throw Error(p.string(), std::nullopt, "cannot read the page file");
    return s;
}

}  // namespace

std::vector<std::string> web_candidates() {
    std::vector<std::string> out;
    if (const char* env = std::getenv("LIDARSCOUT_WEB"); env && *env) out.emplace_back(env);
    if (const std::string dir = executable_dir(); !dir.empty()) {
        const fs::path d(dir);
        out.push_back((d / "web").string());
        out.push_back((d / ".." / "web").lexically_normal().string());
        out.push_back((d / ".." / "share" / "lidarscout" / "web").lexically_normal().string());
    }
    if (*LIDARSCOUT_SOURCE_DIR) out.push_back((fs::path(LIDARSCOUT_SOURCE_DIR) / "web").string());
    return out;
}

std::string default_web_dir() {
    std::string tried;
    for (const auto& d : web_candidates()) {
        std::error_code ec;
        if (fs::is_regular_file(fs::path(d) / "index.html", ec)) return d;
        tried += (tried.empty() ? "" : ", ") + d;
    }
    throw Error("serve: the page's folder (web/ with index.html) was not found; looked in: " + tried);
}

std::map<std::string, WebAsset> read_web_assets(const std::string& dir) {
    std::map<std::string, WebAsset> out;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        const std::string type = content_type_of(entry.path());
        if (!plain_name(name) || type.empty() || entry.is_symlink() || !entry.is_regular_file()) continue;
        out[name] = WebAsset{type, encode(read_whole(entry.path()), 0)};
    }
    if (ec) throw Error(dir, std::nullopt, "cannot list the page's folder: " + ec.message());
    if (!out.contains("index.html")) throw Error(dir, std::nullopt, "the page's folder has no index.html");
    return out;
}

}  // namespace lidarscout::serve
