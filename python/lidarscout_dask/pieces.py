"""One piece of the DEM on a worker: `lidarscout dem --block I/N` in a subprocess, its rasters moved
into the shared pieces directory under their final names by atomic renames, then its record
(PIECE.json, the dem's JSON result) written the same way, last: a piece is finished when its record
exists, so a worker that dies loses only the pieces it was making and a rerun skips the others."""
import json
import os
import shutil
import socket
import subprocess
import time

from lidarscout_dask.plan import program_error


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


def made_files(result):
    """{raster name: path} of a dem JSON result: each product's, or "dem" for one DEM."""
    if "products" in result:
        return dict(result["products"])
    return {"dem": result["output"]}


def run_piece(program, paths, dem_args, pieces_dir, index, count, threads, memory):
    """Makes piece `index` of `count` unless it is finished; returns its record (with "skipped")."""
    record = read_record(pieces_dir, index, count)
    if record is not None:
        return dict(record, skipped=True)
    stem = piece_stem(index, count)
    work = os.path.join(pieces_dir, f".{stem}.work-{socket.gethostname()}-{os.getpid()}")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        command = [program, "dem", *paths, "-o", os.path.join(work, stem + ".tif"), *dem_args,
                   "--block", f"{index}/{count}", "--threads", str(threads), "--json"]
        if memory:
            command += ["--memory", memory]
        t0 = time.monotonic()
        where = f"piece {index}/{count} on {socket.gethostname()}"
        try:
            done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
        except OSError as e:  # raised (a RuntimeError, which Dask carries back): Dask retries the piece
            raise RuntimeError(f"{where}: {program}: cannot run it: {e.strerror}") from None
        seconds = time.monotonic() - t0
        if done.returncode != 0:
            raise RuntimeError(f"{where}: {program_error(done)['message']}")
        result = json.loads(done.stdout)
        files = {}
        for name, path in made_files(result).items():
            final = os.path.basename(path)
            os.replace(path, os.path.join(pieces_dir, final))  # same directory tree: atomic
            files[name] = final
        record = {"index": index, "count": count, "files": files, "host": socket.gethostname(),
                  "seconds": seconds, "points_read": result.get("points_read"),
                  "points_used": result.get("points_used"),
                  "peak_resident_bytes": result.get("peak_resident_bytes"),
                  "memory_estimate_bytes": result.get("memory_estimate_bytes"),
                  "memory_budget_bytes": result.get("memory_budget_bytes"), "block": result.get("block")}
        write_atomic(record_path(pieces_dir, index, count), json.dumps(record, indent=1))
        return dict(record, skipped=False)
    finally:
        shutil.rmtree(work, ignore_errors=True)
