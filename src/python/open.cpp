// open_dataset and crs_summary.
#include "python/open.hpp"

#include "core/error.hpp"
#include "geo/crs_definition.hpp"
#include "geo/projection.hpp"
#include "net/origin_policy.hpp"

namespace lidarscout::python {

dataset::Dataset open_dataset(const std::vector<std::string>& paths, const std::string& crs,
                              const std::string& allow_origins) {
    if (paths.empty()) throw Error("open: give at least one path");
    if (!allow_origins.empty()) net::set_allowed_origins(net::parse_allowed_origins(allow_origins));
    dataset::DatasetOptions options;
    options.crs = crs;
    options.accept_degrees = true;
    dataset::Dataset ds = dataset::open_dataset(paths, options);
    dataset::require_tiles(ds, "open");
    return ds;
}

CrsSummary crs_summary(const std::string& definition) {
    CrsSummary s;
    s.definition = definition;
    if (definition.empty()) return s;
    const geo::CrsInfo info = geo::crs_info(definition);
    s.wkt = info.wkt;
    s.name = info.name;
    const geo::EpsgCodes codes = geo::epsg_codes_of_definition(definition);
    s.epsg = codes.horizontal, s.vertical_epsg = codes.vertical;
    return s;
}

}  // namespace lidarscout::python
