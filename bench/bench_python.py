"""The Python module's figures on ky-jmo335 (run with /usr/bin/python3, PYTHONPATH=build/python):
`ds.read` of a region against `lidarscout clip` of the same region (to .las and to .laz; medians of
--runs, of the wall time and of the CPU time, which a loaded machine disturbs less; each array freed
before the next read), and the peak resident memory of a child process that iter_reads every point in 1 M batches. With
--replica MANIFEST (a virtual replica, `lidarscout synth replicate ... --virtual`): `lidarscout.open(MANIFEST)
.overview()` in a child process against `lidarscout scan MANIFEST --json`, medians of --runs, with peak memory.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [--runs 3] [--cli build/lidarscout]
                                                                  [--replica MANIFEST]
"""

import argparse
import json
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[1]
SURVEY = REPO.parent / "shared" / "data" / "surveys" / "ky-jmo335-eastern-kentucky"
REGIONS = {"corner of 4 tiles": (5679000.0, 3774000.0, 5681000.0, 3776000.0),
           "whole survey": (5673834.0, 3768732.0, 5681835.0, 3776733.0)}

PEAK_CHILD = """
import sys, time
import lidarscout
ds = lidarscout.open(sys.argv[1])
t0 = time.perf_counter()
n = sum(len(b) for b in ds.iter_read(batch=1_000_000))
peak_kib = next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM:"))
print(n, time.perf_counter() - t0, int(peak_kib) / 1024)
"""


OVERVIEW_CHILD = """
import sys
import lidarscout
points = lidarscout.open(sys.argv[1]).overview()
print(len(points))
"""


def cpu_seconds(who):
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def timed(fn, runs, cpu=None):
    """The median wall seconds of `runs` calls of fn and its last result; with `cpu` (RUSAGE_SELF or
    RUSAGE_CHILDREN) the median CPU seconds too: (wall, cpu), result."""
    seconds, cpus = [], []
    for _ in range(runs):
        c0, t0 = cpu_seconds(cpu) if cpu is not None else 0, time.perf_counter()
        result = fn()
        seconds.append(time.perf_counter() - t0)
        cpus.append(cpu_seconds(cpu) - c0 if cpu is not None else 0)
    if cpu is None:
        return statistics.median(seconds), result
    return (statistics.median(seconds), statistics.median(cpus)), result


def clip_seconds(cli, bounds, suffix, runs):
    with tempfile.TemporaryDirectory() as folder:
        out = pathlib.Path(folder) / f"clip{suffix}"
        args = [cli, "clip", str(SURVEY), "-o", str(out), "--force"]
        if bounds:
            args += ["--bounds", ",".join(map(str, bounds))]
        return timed(lambda: subprocess.run(args, check=True, capture_output=True), runs, resource.RUSAGE_CHILDREN)[0]


def child_peak_kib(args):
    """Runs `args` and returns its standard output and its peak resident memory (KiB, wait4's: the child's
    own, the bench's process being small when it forks)."""
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    out = process.stdout.read()
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise SystemExit(f"{args[0]} failed with status {process.returncode}")
    return out, usage.ru_maxrss


def overview_against_scan(cli, manifest, runs):
    scan = [cli, "scan", manifest, "--json"]
    overview = [sys.executable, "-c", OVERVIEW_CHILD, manifest]
    figures = {}
    for name, args in (("scan", scan), ("overview", overview)):
        seconds, (out, peak) = timed(lambda a=args: child_peak_kib(a), runs)
        figures[name] = seconds
        count = json.loads(out)["chunk_points"] if name == "scan" else int(out.split()[0])
        print(f"{name}: {count:,} chunk points, {seconds:.2f} s (median of {runs}), "
              f"peak resident {peak / 1024:.0f} MiB")
    print(f"overview / scan: {figures['overview'] / figures['scan']:.2f}x")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--cli", default=str(REPO / "build" / "lidarscout"))
    parser.add_argument("--replica", help="a virtual replica's replicate.json: overview() against scan only")
    args = parser.parse_args()
    if args.replica:
        return overview_against_scan(args.cli, args.replica, args.runs)
    import lidarscout
    ds = lidarscout.open(str(SURVEY))
    for name, bounds in REGIONS.items():
        (read_s, read_cpu), count = timed(lambda: len(ds.read(bounds=bounds)), args.runs, resource.RUSAGE_SELF)
        las_s, las_cpu = clip_seconds(args.cli, bounds, ".las", args.runs)
        laz_s, laz_cpu = clip_seconds(args.cli, bounds, ".laz", args.runs)
        print(f"{name}: {count:,} points; read {read_s:.2f} s ({read_cpu:.2f} s CPU), clip .las {las_s:.2f} s "
              f"({las_cpu:.2f} s CPU; read {read_s / las_s:.2f}x, CPU {read_cpu / las_cpu:.2f}x), clip .laz "
              f"{laz_s:.2f} s ({laz_cpu:.2f} s CPU; read {read_s / laz_s:.2f}x, CPU {read_cpu / laz_cpu:.2f}x)")
    done = subprocess.run([sys.executable, "-c", PEAK_CHILD, str(SURVEY)], check=True, capture_output=True, text=True)
    n, seconds, peak = done.stdout.split()
    print(f"iter_read of every point in 1 M batches: {int(n):,} points, {float(seconds):.2f} s, "
          f"peak resident {float(peak):.0f} MiB")


if __name__ == "__main__":
    main()
