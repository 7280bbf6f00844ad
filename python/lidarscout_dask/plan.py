"""The pieces of a DEM as `lidarscout dem --plan N --json` prints them (cut by the points the tile
headers hold), and the choice of N."""
import json
import math
import subprocess


def run_json(command):
    """Runs `command` (a list) and returns its standard output parsed as JSON; raises RuntimeError
    with its standard error when it fails."""
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: exit status {done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def plan(program, paths, dem_args, count):
    """The grid and its `count` pieces."""
    return run_json([program, "dem", *paths, "-o", "plan.tif", *dem_args, "--plan", str(count), "--json"])


def parse_bytes(text):
    """"4G", "512M", "1.5G" or a number of bytes (as `lidarscout --memory` takes them)."""
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
    text = text.strip().upper().rstrip("B")
    if text and text[-1] in units:
        return float(text[:-1]) * units[text[-1]]
    return float(text)


def fitting_plan(program, paths, dem_args, count, budget, most):
    """The plan of `count` pieces, doubled until every piece's memory estimate fits `budget` bytes
    (0: no budget) or the grid has no more blocks; the last plan when none fits (its pieces refuse)."""
    while True:
        layout = plan(program, paths, dem_args, count)
        heaviest = max(p["memory_estimate_bytes"] for p in layout["pieces"])
        if not budget or heaviest <= budget or count >= most:
            return layout
        count = min(most, 2 * count)


def choose_count(grid, workers, points_per_piece):
    """Pieces enough to keep every worker busy (4 per worker, so the last ones finish together) and
    none over `points_per_piece` points, at most one per block of the grid."""
    wanted = max(4 * workers, math.ceil(grid["points"] / points_per_piece))
    return max(1, min(wanted, grid["blocks"]))
