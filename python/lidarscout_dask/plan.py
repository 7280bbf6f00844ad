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


def choose_count(grid, workers, points_per_piece):
    """Pieces enough to keep every worker busy (4 per worker, so the last ones finish together) and
    none over `points_per_piece` points, at most one per block of the grid."""
    wanted = max(4 * workers, math.ceil(grid["points"] / points_per_piece))
    return max(1, min(wanted, grid["blocks"]))
