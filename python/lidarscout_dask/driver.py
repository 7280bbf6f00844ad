"""`python3 -m lidarscout_dask dem PATH... -o OUT.tif [--product dtm,dsm,chm] [--texel M] [DEM OPTIONS]
(--scheduler tcp://HOST:8786 | --local N) [--pieces N] [--memory 4G]`: the DEM of `lidarscout dem` made
in pieces on a Dask cluster, through the Python module `lidarscout` (installed on every worker, or
build/python on their PYTHONPATH). The pieces are planned from the tile headers (`ds.dem_plan(N)`, as
`lidarscout dem --plan N`: about equal point counts), submitted heaviest first, each one `ds.dem_block(I, N)`
(`dem --block I/N`) on a worker (pieces.py: retried when it fails; finished pieces kept in the pieces
directory, so a rerun after a dead worker or a stopped driver makes only the missing ones), then mosaicked
(mosaic.py) into OUT.tif, or OUT_NAME.tif per product, equal texel for texel to one `lidarscout dem` run;
the rasters of a run appear together, or none does. dem's options are those of `lidarscout dem` (DEM_OPTIONS
below) but the ones that need the whole raster. The inputs, the output and every option are checked (by
the plan of one piece) before the cluster starts and before anything is written; a failure is one line
(errors.py) and leaves nothing behind but the finished pieces of a run that a rerun can use."""
import argparse
import json
import logging
import os
import shutil
import signal
import statistics
import sys
import time

from lidarscout_dask import pieces as piece_runner
from lidarscout_dask.errors import Failure, closest_name
from lidarscout_dask.mosaic import mosaic
from lidarscout_dask.plan import choose_count, fitting_plan, open_dataset, parse_bytes, plan

# Options of `lidarscout dem` a piece cannot make: they need the whole raster (make them from the mosaic).
REFUSED = ("--hillshade", "--contours", "--rgb", "--from", "--block", "--plan", "--threads", "--force")

# dem's options a piece takes: (option, the module's keyword, help). Their values go to ds.dem_plan and
# ds.dem_block as given (the module checks them, as `lidarscout dem` does).
DEM_OPTIONS = (("--texel", "texel", "texel size in metres (default 1)"),
               ("--bounds", "bounds", "xmin,ymin,xmax,ymax in the CRS's units (default: the whole dataset)"),
               ("--method", "method", "mean (default), min, max, idw, tin"),
               ("--radius", "radius", "idw: search radius, metres"), ("--power", "power", "idw: weights' power"),
               ("--max-edge", "max_edge", "tin and products: the longest triangle edge, metres"),
               ("--product", "product", "dtm,dsm,chm,density,pulse-density,intensity,count (OUT_NAME.tif each)"),
               ("--ground", "ground", "the dtm's ground: classes or smrf"),
               ("--ground-cell", "ground_cell", "smrf: cell, metres"), ("--ground-slope", "ground_slope", "smrf"),
               ("--ground-window", "ground_window", "smrf: window, metres"),
               ("--ground-threshold", "ground_threshold", "smrf: threshold, metres"),
               ("--classes", "classes", "the points' classes (the dtm's ground classes with --product)"),
               ("--returns", "returns", "first,last,single,intermediate"),
               ("--intensity", "intensity", "MIN-MAX"))


class Parser(argparse.ArgumentParser):
    """argparse that fails as the driver does (a Failure of kind "usage"), not with its usage text and status 2."""

    def error(self, message):
        command = "dem: " if self.prog.endswith(" dem") else ""
        raise Failure(f"{command}{message} (see {self.prog} --help)", "usage")


def check_command(argv):
    """The command is dem (or --help): another word is named with the closest one."""
    if argv and argv[0] in ("dem", "-h", "--help"):
        return
    if not argv:
        raise Failure("a command is required: dem (see python3 -m lidarscout_dask --help)", "usage")
    best = closest_name(argv[0], ["dem"])
    raise Failure(f"unknown command '{argv[0]}'" + (f" (did you mean '{best}'?)" if best else " (the command is dem)"),
                  "usage")


def check_own_options(parser, argv):
    """An option close to one of the driver's own but not it (--pices, --locl) is a typo, named here; the
    others that are not the driver's go to `lidarscout dem`, which names its own typos."""
    names = [n for action in parser._actions for n in action.option_strings]
    for arg in argv:
        word = arg.split("=")[0]
        if word.startswith("--") and word not in names:
            best = closest_name(word, [n for n in names if n.startswith("--")])
            if best:
                raise Failure(f"dem: unknown option '{word}' (did you mean '{best}'?)", "usage")


def parse(argv):
    check_command(argv)
    p = Parser(prog="python3 -m lidarscout_dask", allow_abbrev=False,
               description="lidarscout dem on a Dask cluster, in pieces that mosaic exactly")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    d = sub.add_parser("dem", help="a DEM or --product rasters, made in pieces on the workers", allow_abbrev=False)
    d.add_argument("paths", nargs="+", help="LAS/LAZ files, directories or tile lists, as every worker sees them")
    d.add_argument("-o", "--output", required=True, help="the Cloud-Optimized GeoTIFF to write (.tif)")
    where = d.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", help="the Dask scheduler's address, e.g. tcp://head:8786")
    where.add_argument("--local", type=int, metavar="N", help="a LocalCluster of N workers of one thread")
    d.add_argument("--pieces", type=int, default=0,
                   help="pieces to cut the DEM in (default: 4 per worker, more when one would exceed "
                        "--points-per-piece; at most one per block of the grid)")
    d.add_argument("--points-per-piece", type=float, default=200e6, help="(default 2e8)")
    d.add_argument("--memory", default="", help="memory one piece may hold, e.g. 4G (dem --memory; default: "
                                                "half of what the worker's machine may use); without --pieces, "
                                                "the pieces are doubled until each one's estimate fits")
    d.add_argument("--piece-threads", type=int, default=1, help="threads of each piece's dem (default 1)")
    d.add_argument("--retries", type=int, default=2, help="tries more for a piece that fails (default 2)")
    d.add_argument("--crs", default=None, help="the DEM's CRS, e.g. EPSG:32616 (default: the CRS most tiles use)")
    for option, keyword, text in DEM_OPTIONS:
        d.add_argument(option, dest=f"dem_{keyword}", default=None, help=f"dem: {text}")
    d.add_argument("--pieces-dir", default="",
                   help="where the pieces go, shared by every worker (default OUT.pieces beside the output); "
                        "a rerun skips the pieces found there")
    d.add_argument("--keep-pieces", action="store_true", help="keep the pieces after the mosaic")
    d.add_argument("--json", action="store_true", help="print the result as JSON (and an error as JSON)")
    if argv[0] != "dem":
        p.parse_args(argv)  # --help: prints it and exits 0
    check_own_options(d, argv[1:])
    args, rest = d.parse_known_args(argv[1:])
    for option in rest:
        if option.split("=")[0] in REFUSED:
            d.error(f"{option} does not apply to a DEM made in pieces")
    if rest:
        d.error(f"unknown option '{rest[0]}'" if rest[0].startswith("-") else f"unexpected argument '{rest[0]}'")
    return args, dem_options(args)


def dem_options(args):
    """{keyword: value} of the dem options given, as ds.dem_plan and ds.dem_block take them."""
    options = {}
    for _option, keyword, _text in DEM_OPTIONS:
        value = getattr(args, f"dem_{keyword}")
        if value is not None:
            options[keyword] = value
    if "bounds" in options:
        try:
            options["bounds"] = [float(v) for v in options["bounds"].split(",")]
        except ValueError:
            raise Failure(f"dem: --bounds expects four numbers: xmin,ymin,xmax,ymax, not '{options['bounds']}'",
                          "usage") from None
    return options


def check_output(args):
    """The output may not be an input, nor one of the files an input directory holds."""
    out = os.path.realpath(args.output)
    if not out.lower().endswith((".tif", ".tiff")):
        raise Failure(f"{args.output}: the output must be a .tif", file=args.output,
                      cause="the output must be a .tif")
    for path in args.paths:
        real = os.path.realpath(path)
        if out == real or out.startswith(real.rstrip(os.sep) + os.sep) and os.path.exists(out):
            raise Failure(f"{args.output}: the output is an input ({path})", file=args.output,
                          cause=f"the output is an input ({path})")


def check_inputs(paths):
    """Every local input exists (a missing one among others would make every piece fail)."""
    for path in paths:
        if "://" not in path and not os.path.exists(path):
            raise Failure(f"{path}: no such file or folder", file=path, cause="no such file or folder")


def product_outputs(output, files):
    """{raster name: final output}: -o itself for one raster, OUT_NAME.tif for several."""
    if len(files) == 1:
        return {name: output for name in files}
    stem, ext = os.path.splitext(output)
    return {name: f"{stem}_{name}{ext}" for name in files}


def client_for(args):
    from distributed import Client, LocalCluster

    if args.scheduler:
        return Client(args.scheduler), None
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # the workers leave Ctrl-C to the driver (and the pieces)
    try:
        cluster = LocalCluster(n_workers=args.local, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.CRITICAL)  # a failed piece is reported once, by the driver
    finally:
        signal.signal(signal.SIGINT, previous)
    return Client(cluster), cluster


class Bar:
    """A progress bar on stderr: pieces finished of all."""

    def __init__(self, total, label):
        self.total, self.label, self.done, self.t0 = total, label, 0, time.monotonic()

    def add(self, n=1):
        self.done += n
        width = 30
        filled = width * self.done // max(1, self.total)
        sys.stderr.write(f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                         f"{time.monotonic() - self.t0:.0f} s")
        if self.done >= self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()

    def close(self):
        """Ends the line of a bar that stopped early (so that an error starts its own line)."""
        if 0 < self.done < self.total:
            sys.stderr.write("\n")
            sys.stderr.flush()


def run_pieces(client, args, options, count, order, pieces_dir):
    from distributed import as_completed

    piece_options = dict(options, threads=args.piece_threads, memory=parse_bytes(args.memory) if args.memory else 0)
    futures = [client.submit(piece_runner.run_piece, [os.path.abspath(p) for p in args.paths], args.crs,
                             piece_options, pieces_dir, index, count, key=f"lidarscout-piece-{index}-of-{count}",
                             retries=args.retries, pure=False)
               for index in order]
    bar = Bar(len(futures), "lidarscout_dask: pieces")
    records, failures = [], []
    try:
        for future in as_completed(futures):
            try:
                records.append(future.result())
            except Exception as e:  # pylint: disable=broad-except
                # failed every try: the others go on (a rerun makes only the failed ones)
                failures.append(str(e) if isinstance(e, RuntimeError) else f"{type(e).__name__}: {e}")
            bar.add()
    finally:
        bar.close()
    if failures:
        raise Failure(failures[0] + (f" (and {len(failures) - 1} more pieces failed)" if len(failures) > 1 else ""))
    return sorted(records, key=lambda r: r["index"])


def summary(records, outputs, seconds, workers):
    made = [r for r in records if not r["skipped"]]
    times = [r["seconds"] for r in made]
    total_piece_seconds = sum(times)
    out = {"outputs": outputs, "pieces": len(records), "pieces_made": len(made),
           "pieces_skipped": len(records) - len(made), "workers": workers, "seconds": seconds,
           "piece_seconds": {r["index"]: round(r["seconds"], 3) for r in made},
           "piece_seconds_median": statistics.median(times) if times else 0,
           "piece_seconds_max": max(times) if times else 0, "piece_seconds_total": total_piece_seconds,
           "peak_resident_bytes_max": max((r.get("peak_resident_bytes") or 0 for r in made), default=0),
           "memory_estimate_bytes_max": max((r.get("memory_estimate_bytes") or 0 for r in made), default=0),
           "memory_budget_bytes": max((r.get("memory_budget_bytes") or 0 for r in made), default=0)}
    return out


def main(argv):
    args, options = parse(argv)
    check_output(args)
    check_inputs(args.paths)
    budget = parse_bytes(args.memory) if args.memory else 0
    t0 = time.monotonic()
    dataset = open_dataset(args.paths, args.crs)
    grid = plan(dataset, options, 1)  # the module, the inputs and the options, before any work
    pieces_dir = os.path.abspath(args.pieces_dir or args.output + ".pieces")
    client, cluster = client_for(args)
    pieces = PiecesDir(pieces_dir, local=cluster is not None)
    with pieces:  # left once the cluster is closed: a LocalCluster's workers have ended
        try:
            workers = max(1, len(client.scheduler_info()["workers"]))
            count = args.pieces or choose_count(grid, workers, args.points_per_piece)
            layout = fitting_plan(dataset, options, count, 0 if args.pieces else budget, grid["blocks"])
            count = len(layout["pieces"])
            order = [p["index"] for p in sorted(layout["pieces"], key=lambda p: -p["points"])]  # heaviest first
            run = {"paths": [os.path.abspath(p) for p in args.paths], "crs": args.crs, "options": options,
                   "pieces": count}
            check_same_run(pieces_dir, run)
            pieces.make()
            run_path = os.path.join(pieces_dir, "run.json")
            if not os.path.exists(run_path):
                piece_runner.write_atomic(run_path, json.dumps(run, indent=1))
            records = run_pieces(client, args, options, count, order, pieces_dir)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    outputs = product_outputs(args.output, records[0]["files"])
    write_mosaics(pieces_dir, records, outputs)
    result = summary(records, outputs, time.monotonic() - t0, workers)
    if not args.keep_pieces:
        remove_pieces(pieces_dir, records, outputs)
    print_result(args, result, layout)
    return 0


class PiecesDir:
    """The pieces directory, made (make()) when the pieces are about to run. When they fail or are
    interrupted, what this run made goes again (its run.json, the directory itself, the work folders a
    LocalCluster's workers left) unless a finished piece is there for a rerun, which the error then names."""

    def __init__(self, path, local):
        self.path, self.local, self.made, self.created = path, local, False, False

    def __enter__(self):
        return self

    def make(self):
        self.made = True
        try:
            os.makedirs(self.path)
            self.created = True
        except FileExistsError:
            if not os.path.isdir(self.path):
                raise Failure(f"{self.path}: the pieces directory is a file (give another --pieces-dir)",
                              file=self.path, cause="the pieces directory is a file") from None
        except OSError as e:
            raise Failure(f"{self.path}: cannot make the pieces directory: {e.strerror}", file=self.path,
                          cause=f"cannot make the pieces directory: {e.strerror}") from None

    def __exit__(self, kind, error, _traceback):
        if kind is None or not self.made:
            return False
        if self.local:  # the workers have ended: a piece they were making is no one's
            for name in os.listdir(self.path):
                if name.startswith(".piece_") and ".work-" in name:
                    shutil.rmtree(os.path.join(self.path, name), ignore_errors=True)
        finished = [n for n in os.listdir(self.path) if n.startswith("piece_") and n.endswith(".json")]
        if finished:  # named by the error's line (__main__.py for Ctrl-C)
            error.kept = (f"{len(finished)} finished pieces kept in {self.path}: a rerun makes only the others; "
                          "remove it to start again")
            if isinstance(error, Failure):
                error.message += f" ({error.kept})"
        elif not finished and self.created:
            run = os.path.join(self.path, "run.json")
            if os.path.exists(run):
                os.remove(run)
            if not os.listdir(self.path):
                os.rmdir(self.path)
        return False


def write_mosaics(pieces_dir, records, outputs):
    """Every raster of the run mosaicked to a temporary name, then all renamed together: none appears unless
    all do (Ctrl-C waits for the last rename)."""
    bar = Bar(len(outputs), "lidarscout_dask: mosaic")
    made = {}
    try:
        for name, output in outputs.items():
            files = [os.path.join(pieces_dir, r["files"][name]) for r in records]
            made[mosaic(files, os.path.join(pieces_dir, f"mosaic_{name}.vrt"), output, os.cpu_count() or 1)] = output
            bar.add()
        rename_together(made)
        made = {}
    except (RuntimeError, OSError) as e:  # GDAL's errors are RuntimeErrors
        raise Failure(f"the mosaic: {e}") from None
    finally:
        bar.close()
        for temp in made:
            if os.path.exists(temp):
                os.remove(temp)


def rename_together(renames):
    """{temporary: final} renamed with SIGINT and SIGTERM held until the last is done (then raised again)."""
    held = []
    hold = [signal.signal(s, lambda number, _frame: held.append(number)) for s in (signal.SIGINT, signal.SIGTERM)]
    try:
        for temp, final in renames.items():
            os.replace(temp, final)
    finally:
        signal.signal(signal.SIGINT, hold[0])
        signal.signal(signal.SIGTERM, hold[1])
    if held:
        signal.raise_signal(held[0])


def check_same_run(pieces_dir, run):
    """The pieces directory holds the pieces of this run (the same inputs, dem options and pieces), or none."""
    path = os.path.join(pieces_dir, "run.json")
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            if json.load(f) != run:
                raise Failure(f"{pieces_dir} holds the pieces of another run (see its run.json): remove it or give "
                              "another --pieces-dir", file=pieces_dir, cause="it holds the pieces of another run")


def remove_pieces(pieces_dir, records, outputs):
    for r in records:
        for name in r["files"].values():
            os.remove(os.path.join(pieces_dir, name))
        os.remove(piece_runner.record_path(pieces_dir, r["index"], r["count"]))
    for name in outputs:
        os.remove(os.path.join(pieces_dir, f"mosaic_{name}.vrt"))
    os.remove(os.path.join(pieces_dir, "run.json"))
    os.rmdir(pieces_dir)


def print_result(args, result, layout):
    if args.json:
        result["grid"] = {k: layout[k] for k in ("width", "height", "texel_m", "blocks", "tiles", "points")}
        print(json.dumps(result, indent=2))
        return
    for name, output in result["outputs"].items():
        print(f"{output}: {name}, {layout['width']} x {layout['height']} texels of {layout['texel_m']:g} m")
    print(f"{result['pieces']} pieces ({result['pieces_made']} made, {result['pieces_skipped']} found done) on "
          f"{result['workers']} workers in {result['seconds']:.1f} s; per piece median "
          f"{result['piece_seconds_median']:.1f} s, longest {result['piece_seconds_max']:.1f} s; memory per piece: "
          f"peak resident {result['peak_resident_bytes_max'] / 1e9:.3g} GB, estimated "
          f"{result['memory_estimate_bytes_max'] / 1e9:.3g} GB (budget {result['memory_budget_bytes'] / 1e9:.3g} GB)")
