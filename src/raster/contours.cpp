// write_contours: GDALContourGenerateEx into an OGR GeoPackage layer under a temporary name.
#include "raster/contours.hpp"

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "io/output_group.hpp"
#include "io/temporary_files.hpp"
#include "raster/block_raster.hpp"

namespace lidarscout::raster {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
    const std::string gdal = last_gdal_error();
    throw Error(file, std::nullopt, what + (gdal.empty() ? "" : " (GDAL: " + gdal + ")"));
}

int progress_callback(double done, const char*, void* data) {
    const auto* fn = static_cast<const std::function<void(double)>*>(data);
    if (fn && *fn) (*fn)(done);
    return TRUE;
}

// Closes GDAL datasets however the function is left.
struct Closer {
    GDALDataset* dataset = nullptr;
    ~Closer() {
        if (dataset) GDALClose(dataset);
    }
};

// Why a raster has no contour line every `interval`: its heights (nodata left out) hold no multiple
// of it, or it has no height at all.
std::string no_lines_cause(GDALRasterBand* band, double interval) {
    double range[2] = {0, 0};
    CPLPushErrorHandler(CPLQuietErrorHandler);  // an all-nodata band is an answer here, not a failure
    const CPLErr e = band->ComputeRasterMinMax(FALSE, range);
    CPLPopErrorHandler();
    const std::string every = CPLSPrintf("no contour line every %g", interval);
    if (e != CE_None) return every + ": the raster has no height";
    if (range[0] == range[1]) return every + CPLSPrintf(": the raster is flat, at %.6g", range[0]);
    return every + CPLSPrintf(": the heights range from %.6g to %.6g and no line falls between them; give "
                              "--contours under %.3g", range[0], range[1], range[1] - range[0]);
}

}  // namespace

std::string contours_path(const std::string& raster_path) {
    std::filesystem::path p(raster_path);
    p.replace_filename(p.stem().string() + "_contours.gpkg");
    return p.string();
}

std::uint64_t write_contours(const std::string& raster_path, const std::string& gpkg_path, double interval,
                             double nodata, io::OutputGroup& outputs, const std::function<void(double)>& progress) {
    if (!(interval > 0) || !std::isfinite(interval)) {
        throw Error(gpkg_path, std::nullopt, "--contours must be a positive interval");
    }
    GDALAllRegister();
    CPLErrorReset();
    Closer raster{static_cast<GDALDataset*>(GDALOpen(outputs.path_of(raster_path).c_str(), GA_ReadOnly))};
    if (!raster.dataset) fail(raster_path, "cannot open the height raster for its contours");
    GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
    if (!gpkg) fail(gpkg_path, "GDAL has no GPKG driver");
    io::AtomicOutputFile out(gpkg_path);
    std::filesystem::remove(out.temp_path());  // GDAL's GeoPackage makes its own file
    const std::string journal = out.temp_path() + "-journal", wal = out.temp_path() + "-wal";  // SQLite's, beside it
    const io::TemporaryFileGuard journal_guard(journal), wal_guard(wal);  // removed by Ctrl-C too
    std::uint64_t lines = 0;
    {
        Closer vectors{gpkg->Create(out.temp_path().c_str(), 0, 0, 0, GDT_Unknown, nullptr)};
        if (!vectors.dataset) fail(gpkg_path, "cannot create the GeoPackage");
        const OGRSpatialReference* crs = raster.dataset->GetSpatialRef();
        std::unique_ptr<OGRSpatialReference> srs(crs ? crs->Clone() : nullptr);
        OGRLayer* layer = vectors.dataset->CreateLayer("contours", srs.get(), wkbLineString, nullptr);
        if (!layer) fail(gpkg_path, "cannot create the contour layer");
        OGRFieldDefn id("id", OFTInteger64), elevation("elevation", OFTReal);
        if (layer->CreateField(&id) != OGRERR_NONE || layer->CreateField(&elevation) != OGRERR_NONE) {
            fail(gpkg_path, "cannot create the contour attributes");
        }
        char** options = nullptr;
        options = CSLSetNameValue(options, "LEVEL_INTERVAL", CPLSPrintf("%.17g", interval));
        options = CSLSetNameValue(options, "NODATA", CPLSPrintf("%.17g", nodata));
        options = CSLSetNameValue(options, "ID_FIELD", "0");
        options = CSLSetNameValue(options, "ELEV_FIELD", "1");
        if (layer->StartTransaction() != OGRERR_NONE) fail(gpkg_path, "cannot start writing the contours");
        const CPLErr e = GDALContourGenerateEx(raster.dataset->GetRasterBand(1), OGRLayer::ToHandle(layer), options,
                                               progress_callback, const_cast<std::function<void(double)>*>(&progress));
        CSLDestroy(options);
        if (e != CE_None) fail(gpkg_path, "cannot compute the contours");
        if (layer->CommitTransaction() != OGRERR_NONE) fail(gpkg_path, "cannot write the contours");
        lines = static_cast<std::uint64_t>(layer->GetFeatureCount());
    }
    if (CPLGetLastErrorType() >= CE_Failure) fail(gpkg_path, "cannot complete the GeoPackage");
    if (lines == 0) {  // no silent empty product: the temporary GeoPackage goes with `out`
        throw Error(gpkg_path, std::nullopt,
                    no_lines_cause(raster.dataset->GetRasterBand(1), interval) + "; nothing written");
    }
    out.commit(outputs);
    return lines;
}

}  // namespace lidarscout::raster
