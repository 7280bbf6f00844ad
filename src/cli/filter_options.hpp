// The point filter options every command that reads points shares: --classes, --returns and
// --intensity (core/point_filter.hpp), registered once and parsed into a PointFilter.
#pragma once

#include <string>

#include "core/point_filter.hpp"

namespace CLI {
class App;
}

namespace lidarscout::cli {

struct FilterTexts {
    std::string classes, returns, intensity;
    // The filter they name; throws lidarscout::Error naming the option and its valid values.
    PointFilter filter() const { return PointFilter::parse(classes, returns, intensity); }
};

// Adds --classes, --returns and --intensity to `cmd`; `what` says which points they select
// (e.g. "points drawn").
void add_filter_options(CLI::App& cmd, FilterTexts& texts, const std::string& what);

}  // namespace lidarscout::cli
