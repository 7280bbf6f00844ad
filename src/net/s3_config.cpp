// The S3 configuration from the environment and the AWS credentials and config files.
#include "net/s3_config.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>

#include "core/error.hpp"
#include "core/text.hpp"
#include "net/server_text.hpp"

namespace lidarscout::net {

namespace {

namespace fs = std::filesystem;

using Section = std::map<std::string, std::string>;

std::string env(const char* name) {
    const char* value = std::getenv(name);
    return value ? std::string(value) : std::string();
}

std::string trimmed(std::string s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// The section `name` of an INI file ("[name]", then "key = value" lines); nothing when the
// file has no such section. Throws Error when `path` exists but cannot be read.
std::optional<Section> ini_section(const fs::path& path, const std::string& name) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return std::nullopt;
    std::ifstream in(path);
    if (!in) throw Error(path.string(), std::nullopt, "cannot be read");
    std::optional<Section> found;
    bool inside = false;
    for (std::string line; std::getline(in, line);) {
        line = trimmed(line);
        if (line.empty() || line[0] == '#' || line[0] == ';') continue;
        if (line.front() == '[' && line.back() == ']') {
            inside = trimmed(line.substr(1, line.size() - 2)) == name;
            if (inside && !found) found.emplace();
            continue;
        }
        const auto eq = line.find('=');
        if (inside && eq != std::string::npos) (*found)[trimmed(line.substr(0, eq))] = trimmed(line.substr(eq + 1));
    }
    return found;
}

fs::path aws_file(const char* variable, const char* name) {
    if (const std::string set = env(variable); !set.empty()) return set;
    return fs::path(env("HOME")) / ".aws" / name;
}

std::string value_or_empty(const std::optional<Section>& s, const std::string& key) {
    if (!s) return {};
    const auto it = s->find(key);
    return it == s->end() ? std::string() : it->second;
}

// The credentials of the environment, else of the profile.
void read_credentials(S3Config& c, const std::string& profile, bool profile_named) {
    c.access_key = env("AWS_ACCESS_KEY_ID");
    c.secret_key = env("AWS_SECRET_ACCESS_KEY");
    c.session_token = env("AWS_SESSION_TOKEN");
    if (!c.access_key.empty() || !c.secret_key.empty()) {
        if (c.access_key.empty() || c.secret_key.empty()) {
            throw Error("AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY go together: one of them is not set");
        }
        return;
    }
    const fs::path file = aws_file("AWS_SHARED_CREDENTIALS_FILE", "credentials");
    const auto section = ini_section(file, profile);
    if (!section && profile_named) {
        throw Error(file.string(), std::nullopt, "AWS_PROFILE \"" + profile + "\": no such profile in this file");
    }
    c.access_key = value_or_empty(section, "aws_access_key_id");
    c.secret_key = value_or_empty(section, "aws_secret_access_key");
    c.session_token = value_or_empty(section, "aws_session_token");
    if (c.access_key.empty() != c.secret_key.empty()) {
        throw Error(file.string(), std::nullopt, "profile \"" + profile + "\" has only one of aws_access_key_id "
                                                 "and aws_secret_access_key");
    }
}

std::string read_region(const std::string& profile) {
    if (std::string r = env("AWS_REGION"); !r.empty()) return r;
    if (std::string r = env("AWS_DEFAULT_REGION"); !r.empty()) return r;
    const std::string section = profile == "default" ? profile : "profile " + profile;
    const std::string r = value_or_empty(ini_section(aws_file("AWS_CONFIG_FILE", "config"), section), "region");
    return r.empty() ? "us-east-1" : r;
}

std::string read_endpoint() {
    std::string e = env("AWS_ENDPOINT_URL_S3");
    if (e.empty()) e = env("AWS_ENDPOINT_URL");
    while (!e.empty() && e.back() == '/') e.pop_back();
    const std::string lower = ascii_lower(e);
    if (!e.empty() && lower.rfind("http://", 0) != 0 && lower.rfind("https://", 0) != 0) {
        throw Error("AWS_ENDPOINT_URL \"" + e + "\" is not an http(s) URL");
    }
    return e;
}

struct Process {
    std::mutex mutex;
    std::optional<S3Config> config;
    bool requester_pays = false;
};

Process& process() {
    static Process p;
    return p;
}

// The credentials of `c`, for the redaction of what servers answer (net/server_text.hpp).
void remember_credentials(const S3Config& c) {
    for (const auto* value : {&c.access_key, &c.secret_key, &c.session_token}) remember_secret(*value);
}

}  // namespace

bool S3Config::path_style(const std::string& bucket) const {
    if (addressing == "path") return true;
    if (addressing == "virtual") return false;
    return !endpoint.empty() || bucket.find('.') != std::string::npos;  // (a dotted bucket breaks TLS names)
}

S3Config s3_config_from_environment() {
    S3Config c;
    const std::string named = env("AWS_PROFILE");
    const std::string profile = named.empty() ? "default" : named;
    const std::string no_sign = ascii_lower(env("AWS_NO_SIGN_REQUEST"));
    if (no_sign != "yes" && no_sign != "true" && no_sign != "1") read_credentials(c, profile, !named.empty());
    c.region = read_region(profile);
    c.endpoint = read_endpoint();
    c.addressing = ascii_lower(env("AWS_S3_ADDRESSING_STYLE"));
    if (c.addressing == "auto") c.addressing.clear();
    if (!c.addressing.empty() && c.addressing != "path" && c.addressing != "virtual") {
        throw Error("AWS_S3_ADDRESSING_STYLE \"" + c.addressing + "\" is neither \"path\" nor \"virtual\"");
    }
    const std::string payer = ascii_lower(env("AWS_REQUEST_PAYER"));
    if (!payer.empty() && payer != "requester") {
        throw Error("AWS_REQUEST_PAYER \"" + payer + "\": the only value is \"requester\"");
    }
    c.requester_pays = payer == "requester";
    return c;
}

S3Config s3_config() {
    auto& p = process();
    std::lock_guard lock(p.mutex);
    if (!p.config) {
        p.config = s3_config_from_environment();
        remember_credentials(*p.config);
    }
    S3Config c = *p.config;
    c.requester_pays = c.requester_pays || p.requester_pays;
    return c;
}

void set_s3_config(std::optional<S3Config> config) {
    auto& p = process();
    std::lock_guard lock(p.mutex);
    if (config) remember_credentials(*config);
    p.config = std::move(config);
}

void set_s3_requester_pays(bool on) {
    auto& p = process();
    std::lock_guard lock(p.mutex);
    p.requester_pays = on;
}

}  // namespace lidarscout::net
