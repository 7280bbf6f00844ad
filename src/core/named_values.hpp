// Enumerations that the command line names by words (backends, colour modes): one table of
// names indexed by the enumeration's value gives both directions and the error listing them.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace lidarscout {

// The value whose name is `name`; throws lidarscout::Error("unknown <what> '<name>' (known:
// <every name>)") otherwise.
template <typename Enum, std::size_t N>
Enum parse_named(const std::array<std::string_view, N>& names, std::string_view name, std::string_view what) {
    std::string known;
    for (std::size_t i = 0; i < N; ++i) {
        if (name == names[i]) return static_cast<Enum>(i);
        known += (i ? ", " : "") + std::string(names[i]);
    }
    throw Error("unknown " + std::string(what) + " '" + std::string(name) + "' (known: " + known + ")");
}

// The name of `value` (throws lidarscout::Error for a value outside the table).
template <typename Enum, std::size_t N>
std::string_view name_of(const std::array<std::string_view, N>& names, Enum value) {
    const auto i = static_cast<std::size_t>(value);
    if (i >= N) throw Error("no name for value " + std::to_string(i) + " (" + std::to_string(N) + " named)");
    return names[i];
}

}  // namespace lidarscout
