"""Running `lidarscout dem --block I/N` on a Dask cluster (Debian's python3-distributed and python3-gdal):
the DEM of a dataset too large for one machine, cut into pieces by point count, one `lidarscout`
subprocess per piece, mosaicked into one Cloud-Optimized GeoTIFF that equals one whole run."""
