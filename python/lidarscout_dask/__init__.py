"""`lidarscout dem --block I/N` on a Dask cluster (Debian's python3-distributed and python3-gdal): the DEM
of a dataset too large for one machine, cut into pieces by point count, each made on a worker by the
Python module (`ds.dem_block`, the library call `dem --block` makes), mosaicked into one Cloud-Optimized
GeoTIFF that equals one whole run. A piece keeps its memory budget (`--memory`: the piece is refused before
any work when its estimate exceeds it); a piece that fails raises lidarscout.Error, reported with the
piece's name and retried by Dask, and the worker goes on with the others."""
