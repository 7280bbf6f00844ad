// write_hillshade: GDALDEMProcessing("hillshade") to PNG, no .aux.xml sidecar.
#include "raster/hillshade.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "raster/block_raster.hpp"

namespace lidarscout::raster {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
    const std::string gdal = last_gdal_error();
    throw Error(file, std::nullopt, what + (gdal.empty() ? "" : " (GDAL: " + gdal + ")"));
}

}  // namespace

void write_hillshade(const std::string& dem_path, const std::string& png_path) {
    GDALAllRegister();
    CPLErrorReset();
    GDALDatasetH dem = GDALOpen(dem_path.c_str(), GA_ReadOnly);
    if (!dem) fail(dem_path, "cannot open the DEM");
    const char* args[] = {"-of", "PNG", "-compute_edges", "-az", "315", "-alt", "45", nullptr};
    GDALDEMProcessingOptions* options = GDALDEMProcessingOptionsNew(const_cast<char**>(args), nullptr);
    io::AtomicOutputFile out(png_path);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");  // no .aux.xml beside the PNG
    int usage_error = 0;
    GDALDatasetH shade = GDALDEMProcessing(out.temp_path().c_str(), dem, "hillshade", nullptr, options, &usage_error);
    CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
    GDALDEMProcessingOptionsFree(options);
    GDALClose(dem);
    if (!shade) fail(png_path, "cannot compute the hillshade");
    GDALClose(shade);
    if (CPLGetLastErrorType() >= CE_Failure) fail(png_path, "cannot write the hillshade");
    out.commit();
}

}  // namespace lidarscout::raster
