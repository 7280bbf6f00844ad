// BlockRaster: scratch tiled GeoTIFF (GDAL's GTiff driver) -> COG driver -> a temporary file of an output set.
#include "raster/block_raster.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <vector>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "io/output_group.hpp"
#include "io/temporary_files.hpp"

namespace lidarscout::raster {
namespace fs = std::filesystem;

std::string last_gdal_error() {
    const char* msg = CPLGetLastErrorMsg();
    return msg ? msg : "";
}

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
    const std::string gdal = last_gdal_error();
    throw Error(file, std::nullopt, what + (gdal.empty() ? "" : " (GDAL: " + gdal + ")"));
}

GDALDriver* driver(const char* name, const std::string& file) {
    GDALAllRegister();
    GDALDriver* d = GetGDALDriverManager()->GetDriverByName(name);
    if (!d) fail(file, std::string("GDAL has no ") + name + " driver");
    return d;
}

GDALDataType gdal_type(PixelType t) { return t == PixelType::Byte ? GDT_Byte : GDT_Float32; }

std::string scratch_name(const std::string& target) {
    const fs::path p(target);
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    return (dir / ("." + p.filename().string() + ".blocks-" + std::to_string(::getpid()) + ".tif")).string();
}

// Options as GDAL takes them, owned.
class Options {
public:
    void set(const char* key, const std::string& value) { list_ = CSLSetNameValue(list_, key, value.c_str()); }
    char** get() const { return list_; }
    ~Options() { CSLDestroy(list_); }

private:
    char** list_ = nullptr;
};

void set_georeference(GDALDataset& ds, const RasterGeometry& g, const std::string& file) {
    double transform[6] = {g.west, g.pixel_x, 0.0, g.north, 0.0, -g.pixel_y};
    if (ds.SetGeoTransform(transform) != CE_None) fail(file, "cannot set the geotransform");
    if (g.crs_wkt.empty()) return;
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(g.crs_wkt.c_str()) != OGRERR_NONE) fail(file, "GDAL does not understand the CRS");
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (ds.SetSpatialRef(&srs) != CE_None) fail(file, "cannot set the CRS");
}

void describe_bands(GDALDataset& ds, const RasterLayout& layout) {
    for (int b = 1; b <= layout.bands; ++b) {
        GDALRasterBand* band = ds.GetRasterBand(b);
        if (layout.nodata) band->SetNoDataValue(*layout.nodata);
        if (!layout.unit.empty()) band->SetUnitType(layout.unit.c_str());
        if (layout.alpha_last && b == layout.bands) band->SetColorInterpretation(GCI_AlphaBand);
        else if (layout.bands >= 3 && b <= 3) {
            band->SetColorInterpretation(static_cast<GDALColorInterp>(GCI_RedBand + b - 1));
        }
    }
    if (!layout.description.empty()) ds.GetRasterBand(1)->SetDescription(layout.description.c_str());
}

int progress_callback(double done, const char*, void* data) {
    const auto* fn = static_cast<const RasterProgressFn*>(data);
    if (fn && *fn) (*fn)(done);
    return TRUE;
}

}  // namespace

struct BlockRaster::State {
    std::string scratch;
    std::string overview_scratch;  // what GDAL's COG driver writes beside the output while it runs
    std::unique_ptr<io::TemporaryFileGuard> scratch_guard, overview_guard;  // removed on Ctrl-C
    GDALDataset* dataset = nullptr;
    std::mutex mutex;

    ~State() {
        if (dataset) GDALClose(dataset);
        if (!scratch.empty()) VSIUnlink(scratch.c_str());
    }
};

BlockRaster::BlockRaster(std::string target, const RasterGeometry& geometry, const RasterLayout& layout)
    : target_(std::move(target)), geometry_(geometry), layout_(layout), state_(std::make_unique<State>()) {
    if (geometry.width <= 0 || geometry.height <= 0) throw Error(target_, std::nullopt, "the raster would be empty");
    Options options;
    options.set("TILED", "YES");
    options.set("BLOCKXSIZE", "512");
    options.set("BLOCKYSIZE", "512");
    options.set("SPARSE_OK", "TRUE");
    options.set("BIGTIFF", "IF_SAFER");
    if (layout.alpha_last) options.set("ALPHA", "YES");
    if (layout.bands >= 3 && layout.type == PixelType::Byte) options.set("PHOTOMETRIC", "RGB");
    state_->scratch = scratch_name(target_);
    state_->scratch_guard = std::make_unique<io::TemporaryFileGuard>(state_->scratch);
    CPLErrorReset();
    state_->dataset = driver("GTiff", target_)->Create(state_->scratch.c_str(), geometry.width, geometry.height,
                                                        layout.bands, gdal_type(layout.type), options.get());
    if (!state_->dataset) fail(target_, "cannot create the scratch raster " + state_->scratch);
    set_georeference(*state_->dataset, geometry, target_);
    describe_bands(*state_->dataset, layout);
}

BlockRaster::~BlockRaster() = default;

void BlockRaster::write_raw(int band, int x0, int y0, int w, int h, const void* data, std::size_t count,
                            PixelType type) {
    if (count != static_cast<std::size_t>(w) * h || type != layout_.type || band < 1 || band > layout_.bands) {
        throw Error(target_, std::nullopt, "a raster block of the wrong size or type (internal error)");
    }
    std::lock_guard lock(state_->mutex);
    GDALRasterBand* b = state_->dataset->GetRasterBand(band);
    if (b->RasterIO(GF_Write, x0, y0, w, h, const_cast<void*>(data), w, h, gdal_type(type), 0, 0) != CE_None) {
        fail(target_, "cannot write a raster block");
    }
}

void BlockRaster::write(int band, int x0, int y0, int w, int h, std::span<const float> values) {
    write_raw(band, x0, y0, w, h, values.data(), values.size(), PixelType::Float32);
}

void BlockRaster::write(int band, int x0, int y0, int w, int h, std::span<const std::uint8_t> values) {
    write_raw(band, x0, y0, w, h, values.data(), values.size(), PixelType::Byte);
}

void BlockRaster::finish(unsigned threads, io::OutputGroup& outputs, const RasterProgressFn& progress) {
    std::lock_guard lock(state_->mutex);
    CPLErrorReset();
    state_->dataset->FlushCache();
    if (CPLGetLastErrorType() >= CE_Failure) fail(target_, "cannot flush the scratch raster");
    io::AtomicOutputFile out(target_);
    state_->overview_scratch = out.temp_path() + ".ovr.tmp";
    state_->overview_guard = std::make_unique<io::TemporaryFileGuard>(state_->overview_scratch);
    Options options;
    options.set("COMPRESS", "DEFLATE");
    options.set("PREDICTOR", "YES");
    options.set("LEVEL", "1");  // a third faster than the default 6; 2% larger (float heights barely compress)
    options.set("BLOCKSIZE", "512");
    options.set("RESAMPLING", "AVERAGE");
    options.set("NUM_THREADS", std::to_string(std::max(1u, threads)));
    options.set("BIGTIFF", "IF_SAFER");
    GDALDataset* cog = driver("COG", target_)->CreateCopy(out.temp_path().c_str(), state_->dataset, FALSE,
                                                          options.get(), progress_callback,
                                                          const_cast<RasterProgressFn*>(&progress));
    if (!cog) fail(target_, "cannot write the Cloud-Optimized GeoTIFF");
    GDALClose(cog);  // writes what is left; failures show as a GDAL error
    if (CPLGetLastErrorType() >= CE_Failure) fail(target_, "cannot complete the Cloud-Optimized GeoTIFF");
    out.commit(outputs);
}

}  // namespace lidarscout::raster
