"""lidarscout in Python: datasets of LAS/LAZ tiles (files, folders, lists, virtual replicas, EPT, STAC,
http(s) and s3:// URLs) opened in seconds, their overview from chunk points, the points of a region
read in parallel, and DEMs, as numpy arrays. See the README's "Python" section.

    ds = lidarscout.open(paths, crs=None, allow_origins=None)
    ds.tiles, ds.point_count, ds.bounds, ds.crs, ds.skipped, ds.warnings
    ds.overview()                       # every chunk point
    ds.read(bounds=..., classes=[2])    # the points of a region, by the clip's rules
    for batch in ds.iter_read(batch=1_000_000): ...
    raster, geotransform = ds.dem(texel=1.0, product="dtm")
    plan = ds.dem_plan(16, texel=1.0, product="dtm")  # `dem --plan 16`: the pieces of --block I/16
    made = ds.dem_block(3, 16, "dtm.tif", texel=1.0, product="dtm")  # `dem --block 3/16`, written

Errors are raised as lidarscout.Error (file, offset, cause).
"""

from ._error import Error
from ._lidarscout import Dataset, RegionStream, open

__all__ = ["Dataset", "Error", "RegionStream", "open"]
