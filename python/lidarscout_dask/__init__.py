"""Running `lidarscout dem --block I/N` on a Dask cluster (Debian's python3-distributed and python3-gdal):
the DEM of a dataset too large for one machine, cut into pieces by point count, one `lidarscout`
subprocess per piece, mosaicked into one Cloud-Optimized GeoTIFF that equals one whole run.

It runs the program, not the Python module (`import lidarscout`), on purpose: the module's `dem()` makes
one whole raster with a few of dem's options, while the driver needs what only the program does, the plan
of pieces with their memory estimates (`dem --plan N`), a block of the grid (`--block I/N`), every other
option of `dem` passed on as it is, and the products written as the COGs the mosaic joins texel for texel.
A piece in its own process also keeps its `--memory` budget to itself, and a piece that crashes or runs
out of memory ends that process only, not the Dask worker (Dask retries the piece)."""
