// `lidarscout catalog PATH... -o OUT.vpc [--json]`: any dataset lidarscout opens (files, folders,
// tile lists, EPT, STAC catalogs, URLs) written as a QGIS virtual point cloud
// (dataset/catalog_writer.hpp), so that QGIS and PDAL open what we open; with --overview, its overview
// sidecar OUT.overview.laz beside it (dataset/overview_sidecar.hpp), named in the VPC. A virtual replica's
// tiles are named where `synth replicate` without --virtual would write them, beside OUT.vpc.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <filesystem>
#include <memory>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/io_options.hpp"
#include "cli/region_options.hpp"
#include "dataset/catalog_writer.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/overview_writer.hpp"

namespace lidarscout::cli {
namespace {

struct CatalogCliOptions {
    std::vector<std::string> paths;
    std::string output;
    bool json = false;
    bool overview = false;
};

nlohmann::json overview_json(const std::string& path, const dataset::OverviewWriteResult& r) {
    return {{"path", path}, {"tiles", r.tiles}, {"tiles_with_points", r.held}, {"left_out", r.left_out},
            {"points", r.points}, {"bytes", r.bytes}};
}

int run_catalog(const CatalogCliOptions& o) {
    std::vector<dataset::TileSource> sources;  // (kept for a virtual replica's tile names)
    dataset::DatasetOptions options;
    options.sources_found = [&](std::span<const dataset::TileSource> found) {
        if (std::any_of(found.begin(), found.end(), [](const auto& s) { return !s.name.empty(); })) {
            sources.assign(found.begin(), found.end());
        }
    };
    const dataset::Dataset ds = open_region_dataset(o.paths, "", "catalog", false, options);
    dataset::CatalogWriteOptions write;
    write.paths = dataset::catalog_paths(ds, sources, std::filesystem::absolute(o.output).parent_path().string());
    sources = {};
    std::optional<dataset::OverviewWriteResult> overview;
    if (o.overview) {
        write.overview = dataset::overview_path_for(o.output);
        overview = dataset::write_overview(ds, dataset::catalog_ids(ds, write), write.overview);
    }
    const dataset::CatalogWriteResult r = dataset::write_catalog(ds, o.output, write);
    if (o.json) {
        nlohmann::json j = {{"output", o.output},
                            {"items", r.items},
                            {"without_crs", r.without_crs},
                            {"points", ds.point_count},
                            {"skipped", ds.skipped.size()}};
        if (overview) j["overview"] = overview_json(write.overview, *overview);
        print_json_answer(j);
    } else {
        std::printf("%s: %zu tiles, %llu points%s\n", o.output.c_str(), r.items, (unsigned long long)ds.point_count,
                    r.without_crs ? (", " + std::to_string(r.without_crs) + " without a CRS PROJ knows").c_str() : "");
        if (overview) {
            std::printf("%s: %zu tiles (%zu with their %llu chunk points), %zu left out (read themselves)\n",
                        write.overview.c_str(), overview->tiles, overview->held,
                        (unsigned long long)overview->points, overview->left_out);
        }
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
    cmd->add_flag("--overview", o->overview,
                  "Also write OUT.overview.laz beside OUT.vpc: every tile's chunk points and metadata, which open "
                  "the catalog without a request to its tiles (the VPC names it)");
    add_derived_outputs(*cmd, [o] {
        std::vector<io::OutputTarget> out;
        if (o->overview && !o->output.empty()) {
            out.push_back({dataset::overview_path_for(o->output), "-o/--output (--overview)",
                           io::OutputKind::PointCloud});
        }
        return out;
    });
    cmd->callback([o, &run] { run = [o] { return run_catalog(*o); }; });
}

}  // namespace lidarscout::cli
