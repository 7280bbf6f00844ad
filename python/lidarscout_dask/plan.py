"""The pieces of a DEM as `lidarscout dem --plan N --json` prints them (cut by the points the tile
headers hold), and the choice of N. The first plan checks what the run is given before any work: the
program, the inputs, the output and every option `lidarscout dem` gets."""
import json
import math
import subprocess

from lidarscout_dask.errors import Failure


def program_error(done):
    """The `{"error": ...}` a failed `lidarscout ... --json` printed, or one made of its last stderr line."""
    try:
        return json.loads(done.stdout)["error"]
    except (ValueError, KeyError, TypeError):
        lines = [line for line in done.stderr.splitlines() if line.strip()]
        return {"message": f"exit status {done.returncode}" + (f": {lines[-1]}" if lines else ""), "kind": "input"}


def run_json(command):
    """Runs `command` (a list, ending in --json) and returns its standard output parsed as JSON; raises a
    Failure with the program's own error when it fails, or when it cannot be run."""
    try:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    except OSError as e:
        raise Failure(f"{command[0]}: cannot run it: {e.strerror} (--program names lidarscout; default: lidarscout "
                      "on the PATH)", file=command[0], cause=f"cannot run it: {e.strerror}") from None
    if done.returncode != 0:
        raise Failure.of_program(program_error(done))
    return json.loads(done.stdout)


def plan(program, paths, output, dem_args, count):
    """The grid and its `count` pieces (of the DEM `output`, which the plan checks but does not write)."""
    return run_json([program, "dem", *paths, "-o", output, *dem_args, "--plan", str(count), "--json"])


def parse_bytes(text):
    """"4G", "512M", "1.5G" or a number of bytes (as `lidarscout --memory` takes them)."""
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
    text = text.strip().upper().rstrip("B")
    if text and text[-1] in units:
        return float(text[:-1]) * units[text[-1]]
    return float(text)


def fitting_plan(program, paths, output, dem_args, count, budget, most):
    """The plan of `count` pieces, doubled until every piece's memory estimate fits `budget` bytes
    (0: no budget) or the grid has no more blocks; the last plan when none fits (its pieces refuse)."""
    while True:
        layout = plan(program, paths, output, dem_args, count)
        heaviest = max(p["memory_estimate_bytes"] for p in layout["pieces"])
        if not budget or heaviest <= budget or count >= most:
            return layout
        count = min(most, 2 * count)


def choose_count(grid, workers, points_per_piece):
    """Pieces enough to keep every worker busy (4 per worker, so the last ones finish together) and
    none over `points_per_piece` points, at most one per block of the grid."""
    wanted = max(4 * workers, math.ceil(grid["points"] / points_per_piece))
    return max(1, min(wanted, grid["blocks"]))
