"""The pieces' rasters into one Cloud-Optimized GeoTIFF with GDAL's Python bindings: a VRT of the
pieces (gdal.BuildVRT, at the pieces' own resolution so no texel moves), given the first piece's band
description and unit, converted by the COG driver (the options `lidarscout dem` writes with) to a
temporary name beside the output, which the caller renames with the run's other rasters."""
import os

from osgeo import gdal

gdal.UseExceptions()

COG_OPTIONS = ["COMPRESS=DEFLATE", "PREDICTOR=YES", "LEVEL=1", "BLOCKSIZE=512", "RESAMPLING=AVERAGE",
               "BIGTIFF=IF_SAFER"]


def build_vrt(vrt_path, pieces):
    first = gdal.Open(pieces[0])
    transform = first.GetGeoTransform()
    band = first.GetRasterBand(1)
    description, unit = band.GetDescription(), band.GetUnitType()
    first = None
    options = gdal.BuildVRTOptions(resolution="user", xRes=transform[1], yRes=abs(transform[5]))
    vrt = gdal.BuildVRT(vrt_path, pieces, options=options)
    if vrt is None:
        raise RuntimeError(f"{vrt_path}: GDAL cannot build the VRT of the pieces")
    out = vrt.GetRasterBand(1)
    if description:
        out.SetDescription(description)
    if unit:
        out.SetUnitType(unit)
    vrt = None  # written on close


def write_cog(vrt_path, output, threads, progress=None):
    """The COG of `output` at a temporary name beside it, returned (removed if it fails)."""
    temp = os.path.join(os.path.dirname(os.path.abspath(output)), f".{os.path.basename(output)}.tmp-{os.getpid()}")
    try:
        callback = None
        if progress is not None:
            def callback(done, _message, _data):
                progress(done)
                return 1
        options = gdal.TranslateOptions(format="COG", creationOptions=COG_OPTIONS + [f"NUM_THREADS={threads}"],
                                        callback=callback)
        cog = gdal.Translate(temp, vrt_path, options=options)
        if cog is None:
            raise RuntimeError(f"{output}: GDAL cannot write the Cloud-Optimized GeoTIFF")
        cog = None
        return temp
    except BaseException:
        if os.path.exists(temp):
            os.remove(temp)
        raise


def mosaic(pieces, vrt_path, output, threads, progress=None):
    """The pieces (paths) into the COG of `output` through `vrt_path`; returns its temporary name."""
    build_vrt(vrt_path, pieces)
    return write_cog(vrt_path, output, threads, progress)
