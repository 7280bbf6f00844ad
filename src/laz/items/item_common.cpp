// Item coder building blocks defined out of line: the GPS time delta multiple as LASzip
// computes it.
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail {

std::int32_t gps_delta_multiple(std::int32_t delta, std::int32_t last_delta) {
    const float quotient = static_cast<float>(delta) / static_cast<float>(last_delta);
    const double rounded = quotient >= 0 ? double{quotient} + 0.5 : double{quotient} - 0.5;
    // Truncation toward zero keeps the value in range exactly when it lies strictly
    // between these bounds.
    if (!(rounded > -2147483649.0 && rounded < 2147483648.0)) return std::numeric_limits<std::int32_t>::min();
    return static_cast<std::int32_t>(rounded);
}

}  // namespace lidarscout::laz::detail
