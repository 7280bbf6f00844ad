// write_hillshade: GDALDEMProcessing("hillshade") to a GeoTIFF, or to a PNG with its world file
// and .aux.xml written after the PNG is in place (none beside the temporary name).
#include "raster/hillshade.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <vector>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "raster/block_raster.hpp"

namespace lidarscout::raster {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
    const std::string gdal = last_gdal_error();
    throw Error(file, std::nullopt, what + (gdal.empty() ? "" : " (GDAL: " + gdal + ")"));
}

// The georeferencing GDAL keeps for a PNG: `png`.aux.xml (CRS and geotransform) and the world
// file `.pgw` beside it (the geotransform, read by GIS programs that ignore .aux.xml).
void write_png_sidecars(const std::string& png, GDALDatasetH dem) {
    std::array<double, 6> gt{};
    if (GDALGetGeoTransform(dem, gt.data()) != CE_None) fail(png, "the DEM has no geotransform");
    if (!GDALWriteWorldFile(png.c_str(), "pgw", gt.data())) fail(png, "cannot write the world file (.pgw)");
    GDALDatasetH shade = GDALOpen(png.c_str(), GA_ReadOnly);
    if (!shade) fail(png, "cannot reopen the hillshade for its .aux.xml");
    GDALSetGeoTransform(shade, gt.data());
    if (const char* wkt = GDALGetProjectionRef(dem); wkt && *wkt) GDALSetProjection(shade, wkt);
    GDALClose(shade);  // PAM writes PNG.aux.xml
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

void write_hillshade(const std::string& dem_path, const std::string& path) {
    const bool png = hillshade_is_png(path);
    GDALAllRegister();
    CPLErrorReset();
    GDALDatasetH dem = GDALOpen(dem_path.c_str(), GA_ReadOnly);
    if (!dem) fail(dem_path, "cannot open the DEM");
    std::vector<const char*> args = {"-compute_edges", "-az", "315", "-alt", "45", "-of", png ? "PNG" : "GTiff"};
    if (!png) args.insert(args.end(), {"-co", "COMPRESS=DEFLATE", "-co", "TILED=YES"});
    args.push_back(nullptr);
    GDALDEMProcessingOptions* options = GDALDEMProcessingOptionsNew(const_cast<char**>(args.data()), nullptr);
    io::AtomicOutputFile out(path);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");  // no .aux.xml beside the temporary name
    int usage_error = 0;
    GDALDatasetH shade = GDALDEMProcessing(out.temp_path().c_str(), dem, "hillshade", nullptr, options, &usage_error);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
    GDALDEMProcessingOptionsFree(options);
    if (shade) GDALClose(shade);
    if (!shade || CPLGetLastErrorType() >= CE_Failure) {
        GDALClose(dem);
        fail(path, shade ? "cannot write the hillshade" : "cannot compute the hillshade");
    }
    out.commit();
    try {
        if (png) write_png_sidecars(path, dem);
    } catch (...) {
        GDALClose(dem);
        throw;
    }
    GDALClose(dem);
}

}  // namespace lidarscout::raster
