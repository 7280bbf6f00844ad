// Formatting of lidarscout::Error and ErrorRecord messages: "FILE: at byte N: CAUSE".
#include "core/error.hpp"

#include <map>

namespace lidarscout {
namespace {

std::string compose(const std::string& file, std::optional<std::uint64_t> offset,
                    const std::string& cause) {
    std::string msg;
    if (!file.empty()) msg += file + ": ";
    if (offset) msg += "at byte " + std::to_string(*offset) + ": ";
    return msg + cause;
}

}  // namespace

Error::Error(std::string file, std::optional<std::uint64_t> offset, std::string cause)
    : std::runtime_error(compose(file, offset, cause)),
      file_(std::move(file)),
      offset_(offset),
      cause_(std::move(cause)) {}

Error::Error(std::string cause) : Error(std::string(), std::nullopt, std::move(cause)) {}

Error Error::with_file(const std::string& file) const { return Error(file, offset_, cause_); }

ErrorRecord ErrorRecord::of(const Error& error) { return {error.file(), error.offset(), error.cause()}; }

std::string ErrorRecord::message() const { return compose(file, offset, cause); }

std::vector<FileErrors> first_error_per_file(const std::vector<ErrorRecord>& errors) {
    std::vector<FileErrors> out;
    std::map<std::string, std::size_t> index;  // file -> position in out
    for (const auto& e : errors) {
        if (!e.file.empty()) {
            const auto [it, added] = index.emplace(e.file, out.size());
            if (!added) {
                ++out[it->second].count;
                continue;
            }
        }
        out.push_back({e, 1});
    }
    return out;
}

Error Error::in_stage(const std::string& stage, const std::string& cause) { return Error(stage + ": " + cause); }

}  // namespace lidarscout
