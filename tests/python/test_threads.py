"""read, overview and dem release the GIL while they work: a Python thread keeps counting while the main
thread is inside the call. The switch interval is made long (10 s), so that the interpreter never takes the
GIL from the main thread: the counting thread runs only where the main thread gives the GIL up, and gives it
back every 100 ticks (time.sleep(0)). With the GIL held through the call, it counts nothing from the moment
the call starts to the moment it returns; released, it counts for the whole call. Counted, not timed."""

import sys
import threading
import time

import pytest

import lidarscout
from conftest import WOODFORD, run_cli

# Ticks the counting thread must make inside the call: none when the call holds the GIL (checked by building
# the module with the releases taken out: 0 for each call), 35,000 (overview) to 1,400,000 (dem) when it
# releases it (2 cores).
MIN_TICKS_INSIDE = 1_000

# (ky-woodford-county's overview takes under a millisecond: the overview's is that of a virtual replica of 1,600 tiles)
CALLS = {
    "read": lambda woodford, _replica: woodford.read(threads=1),
    "overview": lambda _woodford, replica: replica.overview(threads=1),
    "dem": lambda woodford, _replica: woodford.dem(texel=2.0, threads=1),
}


@pytest.fixture(scope="module")
def replica(tmp_path_factory):
    """A virtual replica of one ky-woodford-county tile on a 40x40 grid (a manifest: no tile copied)."""
    out = tmp_path_factory.mktemp("replica")
    run_cli("synth", "replicate", WOODFORD / "5205000_3900000.laz", "--grid", "40x40", "--virtual", "-o", out,
            "--json")
    return lidarscout.open(str(out / "replicate.json"))


def ticks_inside(call):
    """The ticks a second Python thread counts between the moment `call` starts and the moment it returns."""
    count, stop = [0], threading.Event()

    def tick():
        while not stop.is_set():
            for _ in range(100):
                count[0] += 1
            time.sleep(0)  # (gives the GIL up: 50 us, the timer's slack)

    previous = sys.getswitchinterval()
    sys.setswitchinterval(10.0)
    ticker = threading.Thread(target=tick)
    ticker.start()
    try:
        before = count[0]
        call()
        after = count[0]
    finally:
        stop.set()
        ticker.join()
        sys.setswitchinterval(previous)
    return after - before


@pytest.mark.parametrize("name", sorted(CALLS))
def test_a_python_thread_runs_while_the_call_works(woodford, replica, name):
    CALLS[name](woodford, replica)  # (once before: its first call imports what it needs, which gives the GIL up)
    inside = ticks_inside(lambda: CALLS[name](woodford, replica))
    assert inside > MIN_TICKS_INSIDE, f"{name}: {inside} ticks of another thread while it ran (the GIL held?)"
