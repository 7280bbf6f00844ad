// Server text made fit to show: the credentials remembered, their redaction, the cut.
#include "net/server_text.hpp"

#include <algorithm>
#include <functional>
#include <mutex>
#include <set>
#include <unordered_set>
#include <vector>

#include "core/text.hpp"

namespace lidarscout::net {

namespace {

constexpr std::size_t kShortest = 4;  // a shorter value is no secret
constexpr std::size_t kPiece = 12;    // pieces of a secret this long are redacted wherever they appear

struct Secrets {
    std::mutex mutex;
    std::set<std::string, std::less<>> values;    // (nodes do not move: `pieces` points into them)
    std::unordered_set<std::string_view> pieces;  // every kPiece-long piece of every value
};

Secrets& secrets() {
    static Secrets s;
    return s;
}

// Marks in `covered` the bytes of `text` that are a remembered secret or a piece of one.
void mark_secrets(std::string_view text, std::vector<bool>& covered) {
    auto& s = secrets();
    std::lock_guard lock(s.mutex);
    const auto mark = [&](std::size_t at, std::size_t n) { std::fill_n(covered.begin() + at, n, true); };
    for (const auto& value : s.values) {
        if (value.size() >= kPiece) continue;  // (found by its pieces)
        for (auto at = text.find(value); at != std::string_view::npos; at = text.find(value, at + 1)) {
            mark(at, value.size());
        }
    }
    for (std::size_t at = 0; at + kPiece <= text.size(); ++at) {
        if (s.pieces.contains(text.substr(at, kPiece))) mark(at, kPiece);
    }
}

}  // namespace

void remember_secret(std::string_view secret) {
    if (secret.size() < kShortest) return;
    auto& s = secrets();
    std::lock_guard lock(s.mutex);
    const auto [it, added] = s.values.emplace(secret);
    if (!added) return;
    const std::string_view value = *it;
    for (std::size_t at = 0; at + kPiece <= value.size(); ++at) s.pieces.insert(value.substr(at, kPiece));
}

std::string redact_secrets(std::string_view text) {
    std::vector<bool> covered(text.size(), false);
    mark_secrets(text, covered);
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (!covered[i]) {
            out += text[i];
        } else if (i == 0 || !covered[i - 1]) {
            out += "[redacted]";
        }
    }
    return out;
}

std::string server_text(std::string_view text, std::size_t max) {
    return display_excerpt(redact_secrets(text), max);  // cut at a character, the length named
}

}  // namespace lidarscout::net
