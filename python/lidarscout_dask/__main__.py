"""`python3 -m lidarscout_dask dem PATH... -o OUT.tif ...` (see lidarscout_dask.driver)."""
import sys

from lidarscout_dask.driver import main

sys.exit(main(sys.argv[1:]))
