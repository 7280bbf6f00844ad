"""iter_read keeps memory bounded: all of ky-jmo335 (15.7 M points, 750 MB as one array) in batches of
1 M points in a child process whose peak resident memory is read back (not timed): its own (VmHWM), not
getrusage's, which counts the parent's resident memory at the fork."""

import os
import subprocess
import sys
import textwrap

from conftest import JMO335

CHILD = textwrap.dedent("""
    import sys
    import lidarscout
    ds = lidarscout.open(sys.argv[1])
    n = 0
    for batch in ds.iter_read(batch=1_000_000):
        assert len(batch) <= 1_000_000
        n += len(batch)
    peak_kib = next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM:"))
    print(n, ds.point_count, peak_kib)
""")


# The target: under 300 MB. Measured 198 MiB (2 cores): ~40 MiB the interpreter and libraries, two tables of
# 1 M points (48 MB each: the one Python holds and the one being filled), the rest a read batch's decoded pieces. It was
# 331 MiB while each read batch's kept points were also copied into one (pipelines/region_points.cpp).
PEAK_LIMIT_BYTES = 300_000_000


def test_iter_read_of_every_point_stays_bounded():
    done = subprocess.run([sys.executable, "-c", CHILD, str(JMO335)], capture_output=True, text=True,
                          env=os.environ, check=True)
    read, total, peak_kib = map(int, done.stdout.split())
    assert read == total == 15_677_894
    assert peak_kib * 1024 < PEAK_LIMIT_BYTES, f"peak resident memory {peak_kib * 1024 / 1e6:.0f} MB"
