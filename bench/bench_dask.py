"""Benchmark of the Dask driver (python/lidarscout_dask) against one `lidarscout dem` process:
  /usr/bin/python3 bench/bench_dask.py PATH --dem-args "--texel 10 --product dtm --classes 0"
      [--workers 2] [--threads 2] [--pieces 16] [--runs 3] [--program build/lidarscout]
      [--module build/python]
runs, alternately, `lidarscout dem PATH -o ONE.tif DEM_ARGS --threads THREADS` and the driver (with the
Python module of --module on its PYTHONPATH) on a LocalCluster of WORKERS workers of one thread, RUNS
times each; prints the wall-time medians, their ratio, the per-piece seconds of the last driver run,
whether the decoded rasters are equal byte for byte, and a projection for 100 workers: the dataset's
points at the pieces' measured seconds per point, spread over 100 workers, plus the driver's fixed
time (plan, cluster, mosaic)."""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

from osgeo import gdal


def timed(command, env=None):
    t0 = time.monotonic()
    done = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    if done.returncode != 0:
        sys.exit(f"bench_dask: {' '.join(command)}: {done.stderr.strip()[-2000:]}")
    return time.monotonic() - t0, done.stdout


def same_raster(a, b):
    da, db = gdal.Open(a), gdal.Open(b)
    return (da.GetGeoTransform() == db.GetGeoTransform() and
            da.GetRasterBand(1).ReadRaster() == db.GetRasterBand(1).ReadRaster())


def main():
    p = argparse.ArgumentParser()
    p.add_argument("path")
    p.add_argument("--dem-args", default="--texel 10")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--pieces", type=int, default=16)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--program", default="build/lidarscout")
    p.add_argument("--module", default="build/python", help="the folder of the module lidarscout and the driver")
    a = p.parse_args()
    program = os.path.abspath(a.program)
    dem_args = shlex.split(a.dem_args)
    env = dict(os.environ, PYTHONPATH=os.path.abspath(a.module))  # (the build puts the driver beside the module)
    with tempfile.TemporaryDirectory(prefix="bench_dask_") as tmp:
        one_out, dask_out = os.path.join(tmp, "one.tif"), os.path.join(tmp, "dask.tif")
        one_times, dask_times, result = [], [], {}
        for run in range(a.runs):
            for path in (one_out, dask_out):
                if os.path.exists(path):
                    os.remove(path)
            seconds, _ = timed([program, "dem", a.path, "-o", one_out, *dem_args, "--threads", str(a.threads)])
            one_times.append(seconds)
            seconds, out = timed(["/usr/bin/python3", "-m", "lidarscout_dask", "dem", os.path.abspath(a.path), "-o",
                                  dask_out, *dem_args, "--local", str(a.workers), "--pieces", str(a.pieces),
                                  "--json"], env=env)
            dask_times.append(seconds)
            result = json.loads(out)
            print(f"run {run + 1}: one process {one_times[-1]:.1f} s, driver {dask_times[-1]:.1f} s", flush=True)
        equal = same_raster(one_out, dask_out)
    one, dask = statistics.median(one_times), statistics.median(dask_times)
    pieces = result["piece_seconds"]
    points = result["grid"]["points"]
    per_point = result["piece_seconds_total"] / points
    fixed = max(0.0, dask - result["piece_seconds_total"] / a.workers)
    print(f"one process ({a.threads} threads): median {one:.1f} s of {a.runs}; driver ({a.workers} workers of 1 "
          f"thread, {len(pieces)} pieces): median {dask:.1f} s; ratio {dask / one:.3f}")
    print("per-piece seconds (last run): " + ", ".join(f"{k}: {v:.1f}" for k, v in pieces.items()))
    print(f"piece seconds: total {result['piece_seconds_total']:.1f}, median {result['piece_seconds_median']:.1f}, "
          f"longest {result['piece_seconds_max']:.1f}; peak resident per piece "
          f"{result['peak_resident_bytes_max'] / 1e9:.2f} GB")
    print(f"mosaic equal to the one-process run, byte for byte: {equal}")
    print(f"projection, 100 workers: {points:.3g} points x {per_point * 1e6:.2f} s per M points / 100 + "
          f"{fixed:.0f} s fixed = {points * per_point / 100 + fixed:.0f} s")


if __name__ == "__main__":
    main()
