// read_plain_item: a STAC item of the plain shape from its text (dataset/stac_item_text.hpp).
#include "dataset/stac_item_text.hpp"

#include <simdjson.h>

#include <algorithm>
#include <cmath>

namespace lidarscout::dataset {
namespace {

namespace dom = simdjson::dom;
using Member = std::optional<dom::element>;  // (nullopt: absent)

// The members of `object` named in `names`, in that order (nullopt where absent); false when one is written twice
// (the general reader keeps the last, which this one does not choose).
template <std::size_t N>
bool members(dom::object object, const std::array<std::string_view, N>& names, std::array<Member, N>& out) {
    std::array<bool, N> seen{};
    for (const auto field : object) {
        for (std::size_t k = 0; k < N; ++k) {
            if (field.key != names[k]) continue;
            if (seen[k]) return false;
            seen[k] = true;
            out[k] = field.value;
        }
    }
    return true;
}

// Whether `e` is absent or null: what the general reader takes as no field.
bool absent(const Member& e) { return !e || e->is_null(); }

// The whole number `e` holds, 0 or more, as the general reader's json_optional_count takes it.
std::optional<std::uint64_t> count_of(dom::element e) {
    if (e.type() == dom::element_type::UINT64) return e.get_uint64().value_unsafe();
    if (e.type() == dom::element_type::INT64 && e.get_int64().value_unsafe() >= 0) {
        return static_cast<std::uint64_t>(e.get_int64().value_unsafe());
    }
    return std::nullopt;
}

// proj:bbox as the general reader's bbox_of takes it: 4 or 6 finite numbers, mins before maxes.
std::optional<std::array<double, 6>> bbox_of(dom::element e) {
    dom::array a;
    if (e.get_array().get(a) != simdjson::SUCCESS || (a.size() != 4 && a.size() != 6)) return std::nullopt;
    std::array<double, 6> v{};
    std::size_t n = 0;
    for (const auto x : a) {
        if (!x.is_number() || !std::isfinite(v[n] = x.get_double().value_unsafe())) return std::nullopt;
        ++n;
    }
    return proj_bbox(std::span<const double>(v.data(), n));
}

// The item's properties into `item`; false where the general reader would say a word or choose otherwise.
bool read_properties(dom::element e, PlainItem& item) {
    dom::object props;
    if (e.get_object().get(props) != simdjson::SUCCESS) return false;
    std::array<Member, 5> f;
    if (!members(props, std::array<std::string_view, 5>{"pc:count", "proj:bbox", "proj:epsg", "proj:wkt2",
                                                        "proj:projjson"}, f)) {
        return false;
    }
    if (!absent(f[0]) && !(item.count = count_of(*f[0]))) return false;
    if (!absent(f[1]) && !(item.bbox = bbox_of(*f[1]))) return false;
    if (!absent(f[2])) {  // (a positive whole number, else the general reader goes on to the WKT2 and PROJJSON)
        if (f[2]->type() != dom::element_type::INT64 || f[2]->get_int64().value_unsafe() <= 0) return false;
        item.crs = "EPSG:" + std::to_string(f[2]->get_int64().value_unsafe());
        return true;
    }
    if (!absent(f[4])) return false;  // (PROJJSON: the general reader's own text of it)
    if (absent(f[3])) return true;
    std::string_view wkt;
    if (f[3]->get_string().get(wkt) != simdjson::SUCCESS) return false;
    item.crs = std::string(wkt);
    return true;
}

// The one asset's href; false unless there is exactly one asset, an object with a string href, under a key
// the general reader does not drop.
bool read_href(const Member& e, std::span<const std::string> dropped, PlainItem& item) {
    dom::object assets, asset;
    if (!e || e->get_object().get(assets) != simdjson::SUCCESS || assets.size() != 1) return false;
    const auto only = *assets.begin();
    if (std::find(dropped.begin(), dropped.end(), only.key) != dropped.end()) return false;
    if (only.value.get_object().get(asset) != simdjson::SUCCESS) return false;
    std::array<Member, 1> href;
    std::string_view text;
    if (!members(asset, std::array<std::string_view, 1>{"href"}, href) || !href[0] ||
        href[0]->get_string().get(text) != simdjson::SUCCESS) {
        return false;
    }
    item.href = std::string(text);
    return true;
}

}  // namespace

std::optional<std::array<double, 6>> proj_bbox(std::span<const double> values) {
    if (values.size() != 4 && values.size() != 6) return std::nullopt;
    const std::size_t half = values.size() / 2;
    std::array<double, 6> box{};
    box[2] = box[5] = std::nan("");
    for (std::size_t k = 0; k < half; ++k) box[k] = values[k], box[3 + k] = values[half + k];
    if (!(box[0] <= box[3] && box[1] <= box[4])) return std::nullopt;
    return box;
}

std::optional<PlainItem> read_plain_item(std::string_view text, std::span<const std::string> dropped) {
    thread_local dom::parser parser;
    dom::element root;
    dom::object feature;
    if (parser.parse(text.data(), text.size()).get(root) != simdjson::SUCCESS) return std::nullopt;
    if (root.get_object().get(feature) != simdjson::SUCCESS) return std::nullopt;
    std::array<Member, 4> f;
    if (!members(feature, std::array<std::string_view, 4>{"type", "id", "assets", "properties"}, f)) {
        return std::nullopt;
    }
    std::string_view type, id;
    if (!f[0] || f[0]->get_string().get(type) != simdjson::SUCCESS || type != "Feature") return std::nullopt;
    PlainItem item;
    if (!absent(f[1])) {
        if (f[1]->get_string().get(id) != simdjson::SUCCESS) return std::nullopt;
        item.id = std::string(id);
    }
    if (!read_href(f[2], dropped, item)) return std::nullopt;
    if (!absent(f[3]) && !read_properties(*f[3], item)) return std::nullopt;
    return item;
}

}  // namespace lidarscout::dataset
