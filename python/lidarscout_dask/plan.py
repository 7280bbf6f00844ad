"""The pieces of a DEM as the module's `ds.dem_plan(N, **options)` gives them (`lidarscout dem --plan N`: cut
by the points the tile headers hold), and the choice of N. The first plan checks what the run is given
before any work: the module, the inputs and every option of dem."""
import math

from lidarscout_dask.errors import Failure


def import_module():
    """`lidarscout` (the Python module: build/python on PYTHONPATH, or installed); a Failure when it is missing."""
    try:
        import lidarscout  # pylint: disable=import-outside-toplevel
    except ImportError as e:
        raise Failure(f"cannot import the lidarscout module: {e} (install it, or put build/python on PYTHONPATH)",
                      file=None, cause=f"cannot import the lidarscout module: {e}") from None
    return lidarscout


def failure_of(error, kind="input"):
    """A lidarscout.Error (file, offset, cause) as our Failure."""
    return Failure(str(error), kind, getattr(error, "file", None), getattr(error, "cause", None))


def open_dataset(paths, crs):
    """The dataset of `paths` (lidarscout.open, in `crs` when given); a Failure when it cannot be opened."""
    lidarscout = import_module()
    try:
        return lidarscout.open(paths, crs=crs)
    except lidarscout.Error as e:
        raise failure_of(e) from None


def plan(dataset, options, count):
    """The grid and its `count` pieces, for dem's `options` (what the module's dem_plan returns)."""
    lidarscout = import_module()
    try:
        return dataset.dem_plan(count, **options)
    except lidarscout.Error as e:  # one naming no file refused an option or a combination of them: usage
        raise failure_of(e, "input" if e.file else "usage") from None


def parse_bytes(text):
    """"4G", "512M", "1.5G" or a number of bytes (as `lidarscout --memory` takes them); a Failure otherwise."""
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
    value = text.strip().upper().rstrip("B")
    factor = units.get(value[-1:], 1)
    try:
        number = float(value[:-1] if value[-1:] in units else value)
    except ValueError:
        number = 0
    if not number > 0:
        raise Failure(f"dem: bad --memory '{text}': expected a size such as 512M, 4G or a number of bytes", "usage")
    return int(number * factor)


def fitting_plan(dataset, options, count, budget, most):
    """The plan of `count` pieces, doubled until every piece's memory estimate fits `budget` bytes
    (0: no budget) or the grid has no more blocks; the last plan when none fits (its pieces refuse)."""
    while True:
        layout = plan(dataset, options, count)
        heaviest = max(p["memory_estimate_bytes"] for p in layout["pieces"])
        if not budget or heaviest <= budget or count >= most:
            return layout
        count = min(most, 2 * count)


def choose_count(grid, workers, points_per_piece):
    """Pieces enough to keep every worker busy (4 per worker, so the last ones finish together) and
    none over `points_per_piece` points, at most one per block of the grid."""
    wanted = max(4 * workers, math.ceil(grid["points"] / points_per_piece))
    return max(1, min(wanted, grid["blocks"]))
