// `lidarscout catalog PATH... -o OUT.vpc [--json]`: any dataset lidarscout opens (files, folders,
// tile lists, EPT, STAC catalogs, URLs) written as a QGIS virtual point cloud
// (dataset/catalog_writer.hpp), so that QGIS and PDAL open what we open.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/io_options.hpp"
#include "cli/region_options.hpp"
#include "dataset/catalog_writer.hpp"

namespace lidarscout::cli {
namespace {

struct CatalogCliOptions {
    std::vector<std::string> paths;
    std::string output;
    bool json = false;
};

int run_catalog(const CatalogCliOptions& o) {
    const dataset::Dataset ds = open_region_dataset(o.paths, "", "catalog");
    const dataset::CatalogWriteResult r = dataset::write_catalog(ds, o.output);
    if (o.json) {
        const nlohmann::json j = {{"output", o.output},
                                  {"items", r.items},
                                  {"without_crs", r.without_crs},
                                  {"points", ds.point_count},
                                  {"skipped", ds.skipped.size()}};
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        std::printf("%s: %zu tiles, %llu points%s\n", o.output.c_str(), r.items, (unsigned long long)ds.point_count,
                    r.without_crs ? (", " + std::to_string(r.without_crs) + " without a CRS PROJ knows").c_str() : "");
    }
    return written_exit_status(!ds.skipped.empty());
}

}  // namespace

void register_catalog_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<CatalogCliOptions>();
    auto* cmd = app.add_subcommand("catalog", "Write a dataset as a QGIS virtual point cloud (.vpc, a STAC "
                                              "ItemCollection: each tile's href, count, bounds and CRS)");
    add_inputs(*cmd, "paths", o->paths,
               "LAS/LAZ files, folders (searched recursively), tile lists, EPT, STAC catalogs or URLs")
        ->required();
    add_output(*cmd, "-o,--output", o->output,
               "The .vpc to write (through a temporary name); local tiles are named by relative paths from it",
               io::OutputKind::Catalog)
        ->required();
    cmd->add_flag("--json", o->json, "Print the result as JSON (output, items, without_crs, points, skipped)");
    cmd->callback([o, &run] { run = [o] { return run_catalog(*o); }; });
}

}  // namespace lidarscout::cli
