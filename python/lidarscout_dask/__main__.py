"""`python3 -m lidarscout_dask dem PATH... -o OUT.tif ...` (see lidarscout_dask.driver): a failure is one line
(and a JSON error with --json, errors.py); Ctrl-C one line, then the signal's own end."""
import os
import signal
import sys

from lidarscout_dask.driver import main
from lidarscout_dask.errors import Failure, report, wants_json

ARGV = sys.argv[1:]
try:
    sys.exit(main(ARGV))
except Failure as e:
    report(e, wants_json(ARGV))
    sys.exit(2 if e.kind == "internal" else 1)
except KeyboardInterrupt as e:
    kept = getattr(e, "kept", "")
    sys.stderr.write(f"\nlidarscout_dask: interrupted{f' ({kept})' if kept else ''}\n")
    sys.stderr.flush()
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    os.kill(os.getpid(), signal.SIGINT)
except Exception as e:  # pylint: disable=broad-except  (a defect: still one line, not a traceback)
    report(Failure(f"{type(e).__name__}: {e}", "internal"), wants_json(ARGV))
    sys.exit(2)
