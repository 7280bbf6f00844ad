// The one error type of the library: a message naming the file, the byte offset (when
// known) and the cause. Thrown by every stage; caught at the CLI / viewer edge. Work that goes
// on past a failure (streaming, scanning) keeps the failure as an ErrorRecord: the same three
// fields as a value, for lists in reports and panels.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace lidarscout {

class Error : public std::runtime_error {
public:
    Error(std::string file, std::optional<std::uint64_t> offset, std::string cause);
    // An error without a file (e.g. a bad command-line value).
    explicit Error(std::string cause);

    const std::string& file() const noexcept { return file_; }
    std::optional<std::uint64_t> offset() const noexcept { return offset_; }
    const std::string& cause() const noexcept { return cause_; }

    // An error of a stage without a file, its message prefixed by the stage ("recon: ...").
    static Error in_stage(const std::string& stage, const std::string& cause);

    // A copy of this error attributed to `file` (used when a lower layer did not know it).
    Error with_file(const std::string& file) const;

private:
    std::string file_;
    std::optional<std::uint64_t> offset_;
    std::string cause_;
};

// A failure kept for later: what an Error says, as a value.
struct ErrorRecord {
    std::string file;  // "" when not tied to a file
    std::optional<std::uint64_t> offset;
    std::string cause;

    static ErrorRecord of(const Error& error);
    // "FILE: at byte N: CAUSE", as Error::what().
    std::string message() const;
};

// One record per file (the first, in order) and how many records that file has in all; records
// without a file each stand alone. For lists a person reads: a truncated tile fails once per chunk.
struct FileErrors {
    ErrorRecord first;
    std::size_t count = 1;
};
std::vector<FileErrors> first_error_per_file(const std::vector<ErrorRecord>& errors);

}  // namespace lidarscout
