// Levelled diagnostics: what a stage noticed without failing (a malformed CRS record, a skipped
// source, tiles reprojected), each with its level, the file and byte offset it is about when
// known, and the message. Stages collect them in a Diagnostics list; the CLI edge shows them
// (the message, as before, for people; all fields under --json).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lidarscout {

enum class DiagnosticLevel {
    note,     // worth knowing, nothing is wrong (e.g. what was done about an oddity)
    warning,  // something is off in the input; the result may not be what was meant
};

// "note", "warning".
const char* level_name(DiagnosticLevel level);

struct Diagnostic {
    DiagnosticLevel level = DiagnosticLevel::warning;
    std::string file;                     // "" when not tied to one file
    std::optional<std::uint64_t> offset;  // byte offset in `file`, when known
    std::string message;

    bool operator==(const Diagnostic&) const = default;
};

// A list of diagnostics in the order they were found.
class Diagnostics {
public:
    using const_iterator = std::vector<Diagnostic>::const_iterator;

    void add(Diagnostic d) { items_.push_back(std::move(d)); }
    void warn(std::string message, std::optional<std::uint64_t> offset = std::nullopt) {
        add({DiagnosticLevel::warning, {}, offset, std::move(message)});
    }
    void note(std::string message, std::optional<std::uint64_t> offset = std::nullopt) {
        add({DiagnosticLevel::note, {}, offset, std::move(message)});
    }
    // Appends all of `other`.
    void append(const Diagnostics& other) { items_.insert(items_.end(), other.begin(), other.end()); }
    // Sets `file` on every diagnostic that names none (for lists made below the layer that knows it).
    void attribute_to(const std::string& file);

    // The messages alone, in order: what people are shown and the `warnings` list of --json.
    std::vector<std::string> messages() const;

    bool empty() const { return items_.empty(); }
    std::size_t size() const { return items_.size(); }
    const Diagnostic& operator[](std::size_t i) const { return items_[i]; }
    const Diagnostic& front() const { return items_.front(); }
    const_iterator begin() const { return items_.begin(); }
    const_iterator end() const { return items_.end(); }
    void clear() { items_.clear(); }
    bool operator==(const Diagnostics&) const = default;

private:
    std::vector<Diagnostic> items_;
};

}  // namespace lidarscout
