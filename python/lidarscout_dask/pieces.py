"""One piece of the DEM on a worker: the module's `ds.dem_block(I, N, ...)` (`lidarscout dem --block I/N`)
writing its rasters into a work folder, moved into the shared pieces directory under their final names
by atomic renames, then its record (PIECE.json: what dem_block returned) written the same way, last: a
piece is finished when its record exists, so a worker that dies loses only the pieces it was making and
a rerun skips the others. A piece that fails raises a RuntimeError naming it (Dask retries it); the
worker goes on with its other pieces. The dataset is opened once per worker process and kept."""
import json
import os
import resource
import shutil
import socket
import time

OPENED = {}  # (paths, crs): the dataset, opened once per worker process


def piece_stem(index, count):
    return f"piece_{index:05d}_of_{count:05d}"


def record_path(pieces_dir, index, count):
    return os.path.join(pieces_dir, piece_stem(index, count) + ".json")


def read_record(pieces_dir, index, count):
    """The finished piece's record, or None when it is not finished (or its rasters are missing)."""
    path = record_path(pieces_dir, index, count)
    try:
        with open(path, encoding="utf-8") as f:
            record = json.load(f)
    except (OSError, ValueError):
        return None
    files = record.get("files", {})
    if not files or not all(os.path.isfile(os.path.join(pieces_dir, name)) for name in files.values()):
        return None
    return record


def write_atomic(path, text):
    temp = f"{path}.tmp-{socket.gethostname()}-{os.getpid()}"
    with open(temp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(temp, path)


def dataset(paths, crs):
    import lidarscout  # pylint: disable=import-outside-toplevel  (on the worker)

    key = (tuple(paths), crs)
    if key not in OPENED:
        OPENED[key] = lidarscout.open(paths, crs=crs)
    return OPENED[key]


def make_piece(paths, crs, options, work, stem, index, count):
    """dem_block's result for piece `index`, its rasters in `work`; a RuntimeError naming the piece when it fails."""
    import lidarscout  # pylint: disable=import-outside-toplevel

    try:
        return dataset(paths, crs).dem_block(index, count, os.path.join(work, stem + ".tif"), **options)
    except lidarscout.Error as e:  # raised as a RuntimeError, which Dask carries back: Dask retries the piece
        raise RuntimeError(f"piece {index}/{count} on {socket.gethostname()}: {e}") from None


def run_piece(paths, crs, options, pieces_dir, index, count):
    """Makes piece `index` of `count` unless it is finished; returns its record (with "skipped")."""
    record = read_record(pieces_dir, index, count)
    if record is not None:
        return dict(record, skipped=True)
    stem = piece_stem(index, count)
    work = os.path.join(pieces_dir, f".{stem}.work-{socket.gethostname()}-{os.getpid()}")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        t0 = time.monotonic()
        result = make_piece(paths, crs, options, work, stem, index, count)
        seconds = time.monotonic() - t0
        files = {}
        for name, path in result["outputs"].items():
            final = os.path.basename(path)
            os.replace(path, os.path.join(pieces_dir, final))  # same directory tree: atomic
            files[name] = final
        record = {"index": index, "count": count, "files": files, "host": socket.gethostname(),
                  "seconds": seconds, "points_read": result["points_read"], "points_used": result["points_used"],
                  "peak_resident_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,  # the worker's
                  "memory_estimate_bytes": result["memory_estimate_bytes"],
                  "memory_budget_bytes": result["memory_budget_bytes"], "block": result["block"]}
        write_atomic(record_path(pieces_dir, index, count), json.dumps(record, indent=1))
        return dict(record, skipped=False)
    finally:
        shutil.rmtree(work, ignore_errors=True)
