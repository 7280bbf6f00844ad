// Opening a dataset for Python as the CLI's region commands do (cli/region_options.hpp): every input
// the CLI takes, the frame's CRS as asked (or the most tiles'), in degrees when the data is, the
// other origins its URLs may lead to; refused without a readable tile. Nothing is printed: skipped
// files and warnings stay in the Dataset.
#pragma once

#include <string>
#include <vector>

#include "dataset/dataset.hpp"

namespace lidarscout::python {

// `allow_origins` as `--allow-origins` takes it ("" leaves the process's setting as it is). Throws Error.
dataset::Dataset open_dataset(const std::vector<std::string>& paths, const std::string& crs,
                              const std::string& allow_origins);

// What a CRS definition (dataset::Frame::crs) is: its WKT (WKT2, from PROJ) and EPSG codes (0: none).
struct CrsSummary {
    std::string definition, wkt, name;
    int epsg = 0, vertical_epsg = 0;
};
CrsSummary crs_summary(const std::string& definition);

}  // namespace lidarscout::python
