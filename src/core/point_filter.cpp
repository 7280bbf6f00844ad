// PointFilter: parsing the CLI's filter options, the checks, the description; the viewer's presets
// and the counts per class and return kind.
#include "core/point_filter.hpp"

#include <algorithm>
#include <charconv>
#include <vector>

#include "core/error.hpp"

namespace lidarscout {
namespace {

std::vector<std::string_view> split(std::string_view text, char sep) {
    std::vector<std::string_view> out;
    for (std::size_t at = 0;;) {
        const std::size_t next = text.find(sep, at);
        out.push_back(text.substr(at, next == std::string_view::npos ? std::string_view::npos : next - at));
        if (next == std::string_view::npos) return out;
        at = next + 1;
    }
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    return s;
}

// A whole number in [0, max], or false.
bool whole(std::string_view s, unsigned max, unsigned& out) {
    s = trim(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return !s.empty() && ec == std::errc() && end == s.data() + s.size() && out <= max;
}

std::bitset<256> parse_classes(std::string_view text) {
    std::bitset<256> out;
    const auto bad = [&] {
        return Error("--classes expects class codes 0-255 or ranges of them separated by commas (e.g. 2,9 or 3-5), "
                     "not '" + std::string(text) + "'");
    };
    for (const std::string_view item : split(text, ',')) {
        const auto ends = split(item, '-');
        unsigned lo = 0, hi = 0;
        if (ends.size() > 2 || !whole(ends.front(), 255, lo) || !whole(ends.back(), 255, hi) || lo > hi) throw bad();
        for (unsigned c = lo; c <= hi; ++c) out.set(c);
    }
    return out;
}

std::uint8_t parse_returns(std::string_view text) {
    if (trim(text) == "none") return 0;  // what a filter with every kind unticked writes
    static constexpr std::pair<std::string_view, std::uint8_t> kNames[] = {
        {"first", returns::kFirst}, {"last", returns::kLast}, {"single", returns::kSingle},
        {"intermediate", returns::kIntermediate}};
    std::uint8_t out = 0;
    for (const std::string_view item : split(text, ',')) {
        const auto it = std::find_if(std::begin(kNames), std::end(kNames),
                                     [&](const auto& n) { return n.first == trim(item); });
        if (it == std::end(kNames)) {
            throw Error("--returns expects first, last, single or intermediate separated by commas, not '" +
                        std::string(text) + "'");
        }
        out |= it->second;
    }
    return out;
}

void parse_intensity(std::string_view text, PointFilter& f) {
    const auto ends = split(text, '-');
    unsigned lo = 0, hi = 65535;
    const bool ok = ends.size() == 2 && (trim(ends[0]).empty() || whole(ends[0], 65535, lo)) &&
                    (trim(ends[1]).empty() || whole(ends[1], 65535, hi)) && lo <= hi;
    if (!ok) {
        throw Error("--intensity expects MIN-MAX with 0 <= MIN <= MAX <= 65535 (either may be left out, e.g. "
                    "100-), not '" + std::string(text) + "'");
    }
    f.intensity_min = static_cast<std::uint16_t>(lo), f.intensity_max = static_cast<std::uint16_t>(hi);
}

std::string kinds_list(std::uint8_t kinds) {
    if (kinds == 0) return "none";
    std::string out;
    for (const auto& [bit, name] : {std::pair{returns::kFirst, "first"}, std::pair{returns::kLast, "last"},
                                    std::pair{returns::kSingle, "single"},
                                    std::pair{returns::kIntermediate, "intermediate"}}) {
        if (kinds & bit) out += (out.empty() ? "" : ",") + std::string(name);
    }
    return out;
}

PointFilter only_classes(std::initializer_list<int> codes) {
    PointFilter f;
    f.classes.reset();
    for (const int c : codes) f.classes.set(static_cast<std::size_t>(c));
    return f;
}

PointFilter only_returns(std::uint8_t kinds) {
    PointFilter f;
    f.return_kinds = kinds;
    return f;
}

}  // namespace

std::uint8_t returns::kinds_of(std::uint8_t r, std::uint8_t n) {
    r = std::max<std::uint8_t>(r, 1);
    n = std::max(n, r);
    std::uint8_t kinds = 0;
    if (r == 1) kinds |= kFirst;
    if (r == n) kinds |= kLast;
    if (n == 1) kinds |= kSingle;
    if (r > 1 && r < n) kinds |= kIntermediate;
    return kinds;
}

PointFilter::PointFilter() { classes.set(); }

PointFilter PointFilter::parse(std::string_view classes_text, std::string_view returns_text,
                               std::string_view intensity_text) {
    PointFilter f;
    if (!trim(classes_text).empty()) f.classes = parse_classes(classes_text);
    if (!trim(returns_text).empty()) f.return_kinds = parse_returns(returns_text);
    if (!trim(intensity_text).empty()) parse_intensity(intensity_text, f);
    return f;
}

bool PointFilter::keeps_returns(std::uint8_t r, std::uint8_t n) const {
    return keeps_every_return() || (returns::kinds_of(r, n) & return_kinds) != 0;
}

bool PointFilter::keeps_everything() const {
    return keeps_every_class() && keeps_every_return() && intensity_min == 0 && intensity_max == 65535;
}

std::string PointFilter::class_list() const {
    if (keeps_every_class()) return {};
    std::string out;
    for (unsigned c = 0; c < 256;) {
        if (!classes.test(c)) {
            ++c;
            continue;
        }
        unsigned end = c;
        while (end + 1 < 256 && classes.test(end + 1)) ++end;
        out += (out.empty() ? "" : ",") + std::to_string(c) + (end > c ? "-" + std::to_string(end) : "");
        c = end + 1;
    }
    return out;
}

std::string PointFilter::return_list() const { return keeps_every_return() ? std::string() : kinds_list(return_kinds); }

std::string PointFilter::describe() const {
    if (keeps_everything()) return "all points";
    std::vector<std::string> parts;
    if (!keeps_every_class()) parts.push_back(classes.none() ? "no class" : "classes " + class_list());
    if (!keeps_every_return()) parts.push_back(return_list() + " returns");
    if (intensity_min != 0 || intensity_max != 65535) {
        parts.push_back("intensity " + std::to_string(intensity_min) + "-" + std::to_string(intensity_max));
    }
    std::string out;
    for (const auto& p : parts) out += (out.empty() ? "" : "; ") + p;
    return out;
}

std::span<const FilterPreset> filter_presets() {
    static const FilterPreset kPresets[] = {
        {"All points", PointFilter()},
        {"Ground", only_classes({2})},
        {"Ground + water", only_classes({2, 9})},
        {"Vegetation", only_classes({3, 4, 5})},
        {"Buildings", only_classes({6})},
        {"First returns", only_returns(returns::kFirst)},
    };
    return kPresets;
}

void PointCounts::add(std::uint8_t code, std::uint8_t r, std::uint8_t n) {
    ++by_class[code];
    ++total;
    const std::uint8_t kinds = returns::kinds_of(r, n);
    first += (kinds & returns::kFirst) != 0;
    last += (kinds & returns::kLast) != 0;
    single += (kinds & returns::kSingle) != 0;
    intermediate += (kinds & returns::kIntermediate) != 0;
}

PointCounts& PointCounts::operator+=(const PointCounts& o) {
    for (std::size_t c = 0; c < by_class.size(); ++c) by_class[c] += o.by_class[c];
    first += o.first, last += o.last, single += o.single, intermediate += o.intermediate, total += o.total;
    return *this;
}

}  // namespace lidarscout
