// write_hillshade: GDALDEMProcessing("hillshade") to a GeoTIFF, or to a PNG with its world file
// and .aux.xml, each under a temporary name of the output set.
#include "raster/hillshade.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "io/output_group.hpp"
#include "raster/block_raster.hpp"

namespace lidarscout::raster {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
    const std::string gdal = last_gdal_error();
    throw Error(file, std::nullopt, what + (gdal.empty() ? "" : " (GDAL: " + gdal + ")"));
}

// Closes a GDAL dataset however the function is left.
struct GdalHandle {
    GDALDatasetH handle = nullptr;
    ~GdalHandle() {
        if (handle) GDALClose(handle);
    }
};

// The world file `.pgw` (six lines, as GDALWriteWorldFile writes them: the geotransform, the
// centre of the top-left pixel), read by GIS programs that ignore .aux.xml.
void write_world_file(const std::string& png, const std::array<double, 6>& gt, io::OutputGroup& outputs) {
    char text[256];
    const int n = std::snprintf(text, sizeof text, "%.10f\n%.10f\n%.10f\n%.10f\n%.10f\n%.10f\n", gt[1], gt[4], gt[2],
                                gt[5], gt[0] + 0.5 * gt[1] + 0.5 * gt[2], gt[3] + 0.5 * gt[4] + 0.5 * gt[5]);
    if (n <= 0 || n >= static_cast<int>(sizeof text)) fail(png, "cannot format the world file (.pgw)");
    io::AtomicOutputFile world(std::filesystem::path(png).replace_extension(".pgw").string());
    world.write(std::span(reinterpret_cast<const std::uint8_t*>(text), static_cast<std::size_t>(n)));
    world.commit(outputs);
}

// The georeferencing GDAL keeps for a PNG: `png`.aux.xml (CRS and geotransform), written by GDAL
// beside the PNG's temporary name `temp` and renamed with it, and the world file.
void write_png_sidecars(const std::string& png, const std::string& temp, GDALDatasetH dem, io::OutputGroup& outputs) {
    std::array<double, 6> gt{};
    if (GDALGetGeoTransform(dem, gt.data()) != CE_None) fail(png, "the DEM has no geotransform");
    write_world_file(png, gt, outputs);
    outputs.add(temp + ".aux.xml", png + ".aux.xml");  // guarded before GDAL writes it
    GdalHandle shade{GDALOpen(temp.c_str(), GA_ReadOnly)};
    if (!shade.handle) fail(png, "cannot reopen the hillshade for its .aux.xml");
    GDALSetGeoTransform(shade.handle, gt.data());
    if (const char* wkt = GDALGetProjectionRef(dem); wkt && *wkt) GDALSetProjection(shade.handle, wkt);
    GDALClose(shade.handle);  // PAM writes TEMP.aux.xml
    shade.handle = nullptr;
    if (CPLGetLastErrorType() >= CE_Failure) fail(png, "cannot write the hillshade's .aux.xml");
}

}  // namespace

bool hillshade_is_png(const std::string& path) {
    std::string ext = path.substr(std::min(path.size(), path.find_last_of('.')));
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png") return true;
    if (ext == ".tif" || ext == ".tiff") return false;
    throw Error(path, std::nullopt, "the hillshade must end in .tif (GeoTIFF) or .png (with a world file)");
}

void write_hillshade(const std::string& dem_path, const std::string& path, io::OutputGroup& outputs) {
    const bool png = hillshade_is_png(path);
    GDALAllRegister();
    CPLErrorReset();
    GdalHandle dem{GDALOpen(outputs.path_of(dem_path).c_str(), GA_ReadOnly)};
    if (!dem.handle) fail(dem_path, "cannot open the DEM");
    std::vector<const char*> args = {"-compute_edges", "-az", "315", "-alt", "45", "-of", png ? "PNG" : "GTiff"};
    if (!png) args.insert(args.end(), {"-co", "COMPRESS=DEFLATE", "-co", "TILED=YES"});
    args.push_back(nullptr);
    io::AtomicOutputFile out(path);
    GDALDEMProcessingOptions* options = GDALDEMProcessingOptionsNew(const_cast<char**>(args.data()), nullptr);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");  // no .aux.xml yet: the sidecars below write it
    int usage_error = 0;
    GDALDatasetH shade =
        GDALDEMProcessing(out.temp_path().c_str(), dem.handle, "hillshade", nullptr, options, &usage_error);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
    GDALDEMProcessingOptionsFree(options);
    if (shade) GDALClose(shade);
    if (!shade || CPLGetLastErrorType() >= CE_Failure) {
        fail(path, shade ? "cannot write the hillshade" : "cannot compute the hillshade");
    }
    out.commit(outputs);
    if (png) write_png_sidecars(path, out.temp_path(), dem.handle, outputs);
}

}  // namespace lidarscout::raster
