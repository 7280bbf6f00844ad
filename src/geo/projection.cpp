// PROJ behind crs_info, CrsTransform and lonlat_bounds. Each object owns its PROJ context, so
// objects never share PROJ state across threads.
#include "geo/projection.hpp"

#include <proj.h>
#include <strings.h>

#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::geo {
namespace {

[[noreturn]] void fail(const std::string& cause) { throw Error::in_stage("geo", cause); }

// A PROJ context with its objects, released together.
class Context {
public:
    Context() : ctx_(proj_context_create()) {
        if (!ctx_) fail("cannot create a PROJ context");
        proj_log_level(ctx_, PJ_LOG_NONE);
    }
    ~Context() {
        for (PJ* p : objects_) proj_destroy(p);
        proj_context_destroy(ctx_);
    }
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    PJ_CONTEXT* get() const { return ctx_; }
    // Takes ownership of `p`; throws with `what` when it is null.
    PJ* own(PJ* p, const std::string& what) {
        if (!p) fail(what + ": " + proj_context_errno_string(ctx_, proj_context_errno(ctx_)));
        objects_.push_back(p);
        return p;
    }
    PJ* crs(const std::string& definition) {
        if (definition.empty()) fail("no CRS given");
        PJ* p = own(proj_create(ctx_, definition.c_str()),
                    "PROJ does not understand the CRS '" + shorten(definition) + "'");
        if (!proj_is_crs(p)) fail("'" + shorten(definition) + "' is not a coordinate reference system");
        refuse_fuzzy_name(definition, p);
        return p;
    }

    // PROJ takes a bare word for a CRS name and picks the nearest one ("foo" -> "Amersfoort"):
    // only an exact name (any case) is accepted that way.
    static void refuse_fuzzy_name(const std::string& definition, PJ* p) {
        if (definition.find_first_of(":+[{") != std::string::npos) return;  // EPSG:n, a PROJ string, WKT, PROJJSON
        const char* name = proj_get_name(p);
        if (name && strcasecmp(name, definition.c_str()) == 0) return;
        fail("unknown CRS '" + shorten(definition) + "' (give EPSG:code, WKT or a PROJ string; PROJ's nearest "
             "name is '" + std::string(name ? name : "?") + "')");
    }

    static std::string shorten(const std::string& s) { return s.size() > 80 ? s.substr(0, 77) + "..." : s; }

private:
    PJ_CONTEXT* ctx_;
    std::vector<PJ*> objects_;
};

// A bound CRS (WKT with TOWGS84) stands for its source CRS.
PJ* unbound(Context& c, PJ* crs) {
    if (proj_get_type(crs) != PJ_TYPE_BOUND_CRS) return crs;
    return c.own(proj_get_source_crs(c.get(), crs), "bound CRS without a source");
}

// Metres per unit of the first axis of `crs`; NaN when the axis is angular.
double first_axis_to_metres(Context& c, PJ* crs) {
    PJ* cs = c.own(proj_crs_get_coordinate_system(c.get(), crs), "CRS without a coordinate system");
    double factor = 0;
    if (!proj_cs_get_axis_info(c.get(), cs, 0, nullptr, nullptr, nullptr, &factor, nullptr, nullptr, nullptr)) {
        fail("cannot read the CRS's axes");
    }
    return factor;
}

bool is_geographic(PJ* crs) {
    const PJ_TYPE t = proj_get_type(crs);
    return t == PJ_TYPE_GEOGRAPHIC_2D_CRS || t == PJ_TYPE_GEOGRAPHIC_3D_CRS || t == PJ_TYPE_GEOGRAPHIC_CRS;
}

// What PROJ says of `definition`, asked anew (a context of its own: PROJ opens its database for it).
CrsInfo make_crs_info(const std::string& definition) {
    Context c;
    PJ* crs = unbound(c, c.crs(definition));
    CrsInfo info;
    if (const char* name = proj_get_name(crs)) info.name = name;
    if (const char* wkt = proj_as_wkt(c.get(), crs, PJ_WKT2_2019, nullptr)) info.wkt = wkt;
    PJ* horizontal = crs;
    PJ* vertical = nullptr;
    if (proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
        horizontal = unbound(c, c.own(proj_crs_get_sub_crs(c.get(), crs, 0), "compound CRS without a horizontal part"));
        vertical = unbound(c, c.own(proj_crs_get_sub_crs(c.get(), crs, 1), "compound CRS without a vertical part"));
    } else if (proj_get_type(crs) == PJ_TYPE_VERTICAL_CRS) {
        fail("'" + Context::shorten(definition) + "' is a vertical CRS only; x and y need a horizontal one");
    }
    info.geographic = is_geographic(horizontal);
    info.xy_to_metres = info.geographic ? std::nan("") : first_axis_to_metres(c, horizontal);
    info.has_vertical = vertical != nullptr;
    info.z_to_metres = vertical ? first_axis_to_metres(c, vertical) : info.xy_to_metres;
    return info;
}

// What `make(definition)` gave, kept per definition (the last 64 of each kind T; `made` counts the calls of make):
// each asks PROJ's database (milliseconds), and a survey's or a catalog's thousands of tiles share a few CRSs.
// A definition make throws for is not kept.
template <typename T, typename Make>
T kept_per_definition(const std::string& definition, std::atomic<std::size_t>& made, Make&& make) {
    constexpr std::size_t kKept = 64;
    static std::mutex mutex;
    static std::map<std::string, T> kept;
    std::lock_guard lock(mutex);
    if (const auto it = kept.find(definition); it != kept.end()) return it->second;
    T value = make(definition);
    made.fetch_add(1);
    if (kept.size() >= kKept) kept.clear();
    kept.emplace(definition, value);
    return value;
}

std::atomic<std::size_t> g_crs_infos_made{0};

}  // namespace

// (`lidarscout catalog` of 152,100 tiles of one CRS asked PROJ anew for every item: 280 of its 300 s.)
CrsInfo crs_info(const std::string& definition) {
    return kept_per_definition<CrsInfo>(definition, g_crs_infos_made, make_crs_info);
}

std::string crs_wkt1(const std::string& definition) {
    Context c;
    const char* wkt = proj_as_wkt(c.get(), c.crs(definition), PJ_WKT1_GDAL, nullptr);
    if (!wkt) fail("PROJ cannot write the CRS '" + Context::shorten(definition) + "' as WKT 1");
    return wkt;
}

bool proj_knows_crs(const std::string& definition) {
    static std::mutex mutex;
    static std::map<std::string, bool> known;
    std::lock_guard lock(mutex);
    if (const auto it = known.find(definition); it != known.end()) return it->second;
    bool ok = true;
    try {
        Context c;
        c.crs(definition);
    } catch (const Error&) {
        ok = false;
    }
    if (known.size() >= 256) known.clear();
    return known[definition] = ok;
}

void fall_back_to_horizontal(las::Crs& crs) {
    if (!crs.epsg || !crs.vertical_epsg || !crs.vertical_usable) return;
    const std::string horizontal = "EPSG:" + std::to_string(*crs.epsg);
    const std::string compound = horizontal + "+" + std::to_string(*crs.vertical_epsg);
    if (proj_knows_crs(compound) || !proj_knows_crs(horizontal)) return;
    crs.vertical_usable = false;
    crs.warnings.warn(vertical_fallback_message(crs));
}

std::string vertical_fallback_message(const las::Crs& crs) {
    if (crs.vertical_usable || !crs.epsg || !crs.vertical_epsg) return {};
    const std::string horizontal = "EPSG:" + std::to_string(*crs.epsg);
    return "PROJ does not know the vertical CRS EPSG:" + std::to_string(*crs.vertical_epsg) + " of " + horizontal +
           "+" + std::to_string(*crs.vertical_epsg) + ": placed by its horizontal CRS " + horizontal +
           " alone, heights kept as stored (" + las::unit_name(crs.vertical_unit) + ")";
}

struct CrsTransform::State {
    Context context;
    PJ* transform = nullptr;
    mutable std::mutex mutex;
};

CrsTransform::CrsTransform(const std::string& source, const std::string& target)
    : source_(source), target_(target), state_(std::make_unique<State>()) {
    Context& c = state_->context;
    PJ* src = c.crs(source);
    PJ* dst = c.crs(target);
    heights_ = proj_get_type(unbound(c, src)) == PJ_TYPE_COMPOUND_CRS &&
               proj_get_type(unbound(c, dst)) == PJ_TYPE_COMPOUND_CRS;
    PJ* raw = c.own(proj_create_crs_to_crs_from_pj(c.get(), src, dst, nullptr, nullptr),
                    "no transformation from '" + Context::shorten(source) + "' to '" + Context::shorten(target) + "'");
    // x east / y north (longitude first) whatever the axis order the CRSs declare.
    state_->transform = c.own(proj_normalize_for_visualization(c.get(), raw), "cannot normalise the axis order");
}

CrsTransform::~CrsTransform() = default;

void CrsTransform::apply(std::span<double> x, std::span<double> y, std::span<double> z) const {
    if (x.size() != y.size() || (!z.empty() && z.size() != x.size())) fail("coordinate arrays of different lengths");
    if (x.empty()) return;
    std::lock_guard lock(state_->mutex);
    const std::size_t n = x.size();
    proj_trans_generic(state_->transform, PJ_FWD, x.data(), sizeof(double), n, y.data(), sizeof(double), n,
                       z.empty() ? nullptr : z.data(), sizeof(double), z.empty() ? 0 : n, nullptr, 0, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
            fail("a point cannot be transformed from '" + Context::shorten(source_) + "' to '" +
                 Context::shorten(target_) + "' (outside the area the CRSs cover)");
        }
    }
}

void CrsTransform::apply(double& x, double& y, double& z) const {
    apply(std::span<double>(&x, 1), std::span<double>(&y, 1), std::span<double>(&z, 1));
}

std::string CrsTransform::ballpark_at(double x, double y, double z) const {
    std::lock_guard lock(state_->mutex);
    PJ_CONTEXT* ctx = state_->context.get();
    const PJ_COORD out = proj_trans(state_->transform, PJ_FWD, proj_coord(x, y, z, 0));
    if (!std::isfinite(out.xyz.x)) return {};  // outside the CRSs' area: apply() says so
    PJ* used = proj_trans_get_last_used_operation(state_->transform);
    if (!used) return {};
    std::string name;
    if (proj_coordoperation_has_ballpark_transformation(ctx, used)) {
        const char* n = proj_get_name(used);
        name = n ? n : "unnamed operation";
    }
    proj_destroy(used);
    return name;
}

void CrsTransform::apply_bounds(double& min_x, double& min_y, double& max_x, double& max_y) const {
    std::lock_guard lock(state_->mutex);
    double out[4];
    if (!proj_trans_bounds(state_->context.get(), state_->transform, PJ_FWD, min_x, min_y, max_x, max_y, &out[0],
                           &out[1], &out[2], &out[3], 21)) {
        fail("the bounds cannot be transformed from '" + Context::shorten(source_) + "' to '" +
             Context::shorten(target_) + "'");
    }
    min_x = out[0];
    min_y = out[1];
    max_x = out[2];
    max_y = out[3];
}

namespace {

std::atomic<std::size_t> g_lonlat_made{0};

// Transforms to lon/lat kept per source CRS.
std::shared_ptr<const CrsTransform> to_lonlat(const std::string& definition) {
    return kept_per_definition<std::shared_ptr<const CrsTransform>>(
        definition, g_lonlat_made,
        [](const std::string& d) { return std::make_shared<const CrsTransform>(d, "EPSG:4326"); });
}

}  // namespace

std::size_t lonlat_transforms_made() { return g_lonlat_made.load(); }
std::size_t crs_infos_made() { return g_crs_infos_made.load(); }

LonLatBounds lonlat_bounds(const std::string& definition, double min_x, double min_y, double max_x, double max_y) {
    to_lonlat(definition)->apply_bounds(min_x, min_y, max_x, max_y);
    return {min_x, min_y, max_x, max_y};
}

}  // namespace lidarscout::geo
