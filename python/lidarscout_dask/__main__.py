"""`python3 -m lidarscout_dask dem PATH... -o OUT.tif ...` (see lidarscout_dask.driver)."""
import sys

from lidarscout_dask.driver import main

try:
    sys.exit(main(sys.argv[1:]))
except RuntimeError as e:  # a failed command or piece: one line naming it
    sys.exit(f"lidarscout_dask: {e}")
