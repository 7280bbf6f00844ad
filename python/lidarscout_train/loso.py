"""Helpers of scripts/loso_eval.sh (leave-one-survey-out evaluation of the heightmap network).

    python3 -m lidarscout_train.loso stride DATA.bin [CHUNK_POINTS]
        the chunk-point stride of the file's first sample (the auto stride: about 369 chunk
        points per window), or the stride that gives CHUNK_POINTS per window instead
    python3 -m lidarscout_train.loso table EVAL.json... [--released-dir DIR] [--json OUT]
        one row per held-out survey (each file: `lidarscout eval --json` of one survey, named
        SURVEY[.TAG].json), with linear, cnn and (when present) released RMSE, the ratios to
        linear, the colour PSNR, and the mean ratios over surveys. The released model's figures
        come from the file itself or from DIR/SURVEY[.TAG].json (an eval of the same patches:
        its linear RMSE must be the same, else the patches differ and this fails)
    python3 -m lidarscout_train.loso table EVAL.json... --shipped-dir DIR [--released-dir DIR] [--json OUT]
        the same, with a "shipped" column beside "cnn": the cnn method of DIR/SURVEY[.TAG].json (an
        eval of the same patches with another model, e.g. the shipped one against a candidate)
"""
import json
import math
import os
import struct
import sys

AUTO_CHUNK_POINTS = 20.0 * 960.0 ** 2 / 50_000.0  # the stride rule of src/pipelines/survey_samples.hpp


def file_stride(path):
    """The stride recorded in a train-data file's first sample."""
    with open(path, "rb") as f:
        pre = f.read(48)
        if pre[:8] != b"LSTRAIN1":
            raise SystemExit(f"{path}: not a train-data file")
        _, _, count, meta_offset, meta_length = struct.unpack("<5Q", pre[8:])
        if count == 0:
            raise SystemExit(f"{path}: no samples")
        f.seek(meta_offset)
        return int(json.loads(f.read(meta_length))["samples"][0]["stride"])


def stride_for(auto_stride, chunk_points):
    """The stride giving about chunk_points per window, from the auto stride (about 369)."""
    return max(1, round(auto_stride * AUTO_CHUNK_POINTS / chunk_points))


def _method(e, name, key):
    m = e["methods"].get(name)
    return None if m is None else m.get(key)


def _method_from(e, path, method, as_name):
    """Copies `method` of the eval file `path` into e as `as_name`, after checking both scored the
    same patches (same patch count and linear RMSE, the latter to 1e-7 relative: builds that sum in another
    order differ in the tenth digit)."""
    with open(path) as f:
        r = json.load(f)
    for key in ("rmse_m_mean", "patches"):
        a, b = _method(e, "linear", key), _method(r, "linear", key)
        if a != b and not (a is not None and b is not None and abs(a - b) <= 1e-7 * max(abs(a), abs(b), 1.0)):
            raise SystemExit(f"{path}: not the same patches as the CNN's evaluation (linear {key} {b} != {a})")
    if method in r["methods"]:
        e["methods"][as_name] = r["methods"][method]


def rows_of(paths, released_dir=None, shipped_dir=None):
    rows = []
    for p in paths:
        with open(p) as f:
            e = json.load(f)
        for folder, method, as_name in ((released_dir, "released", "released"), (shipped_dir, "cnn", "shipped")):
            if folder and os.path.exists(os.path.join(folder, os.path.basename(p))):
                _method_from(e, os.path.join(folder, os.path.basename(p)), method, as_name)
        tag = os.path.basename(p)[: -len(".json")]
        patches = _method(e, "linear", "patches") or 0
        lin = _method(e, "linear", "rmse_m_mean")
        row = {"survey": tag, "patches": patches, "linear": lin, "cnn": _method(e, "cnn", "rmse_m_mean"),
               "released": _method(e, "released", "rmse_m_mean"),
               "psnr_linear": _method(e, "linear", "psnr_db_mean"), "psnr_cnn": _method(e, "cnn", "psnr_db_mean")}
        if shipped_dir:
            row |= {"shipped": _method(e, "shipped", "rmse_m_mean"),
                    "psnr_shipped": _method(e, "shipped", "psnr_db_mean")}
        for k in ("cnn", "released", "shipped"):
            if k not in row:
                continue
            row[k + "_ratio"] = row[k] / lin if (row[k] is not None and lin) else None
        rows.append(row)
    return rows


def _fmt(v, spec):
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def _mean(rows, key):
    vals = [r[key] for r in rows if r[key] is not None and r["patches"]]
    return sum(vals) / len(vals) if vals else None


def print_table(rows):
    """A markdown table; the shipped model's columns (before the CNN's) when the rows have them."""
    models = (["shipped"] if rows and "shipped" in rows[0] else []) + ["cnn", "released"]
    names = {"shipped": "shipped CNN", "cnn": "CNN", "released": "released"}
    head = "".join(f" {names[m]} RMSE (m) | {names[m]} / linear |" for m in models)
    print(f"| held-out survey | patches | linear RMSE (m) |{head} RGB PSNR linear → CNN (dB) |")
    print("|---|---|---|" + "---|---|" * len(models) + "---|")
    for r in rows:
        psnr = "–" if r["psnr_cnn"] is None else f"{r['psnr_linear']:.2f} → {r['psnr_cnn']:.2f}"
        if r.get("psnr_shipped") is not None and r["psnr_cnn"] is not None:
            psnr = f"{r['psnr_linear']:.2f} → {r['psnr_shipped']:.2f} (shipped), {r['psnr_cnn']:.2f}"
        cells = "".join(f" {_fmt(r[m], '.3f')} | {_fmt(r[m + '_ratio'], '.3f')} |" for m in models)
        print(f"| {r['survey']} | {r['patches']} | {_fmt(r['linear'], '.3f')} |{cells} {psnr} |")
    means = "".join(f" | {_fmt(_mean(rows, m + '_ratio'), '.3f')} |" for m in models)
    print(f"| **mean over surveys** | {sum(r['patches'] for r in rows)} | |{means} |")


def _option(args, name):
    """(value, the other args) for `name VALUE` in args; value None when absent."""
    if name not in args:
        return None, args
    i = args.index(name)
    return args[i + 1], args[:i] + args[i + 2:]


def main(argv):
    if len(argv) >= 2 and argv[0] == "stride":
        auto = file_stride(argv[1])
        print(stride_for(auto, float(argv[2])) if len(argv) > 2 else auto)
    elif len(argv) >= 2 and argv[0] == "table":
        paths = argv[1:]
        out, paths = _option(paths, "--json")
        released_dir, paths = _option(paths, "--released-dir")
        shipped_dir, paths = _option(paths, "--shipped-dir")
        rows = rows_of(paths, released_dir, shipped_dir)
        print_table(rows)
        if out:
            means = {f"mean_{m}_ratio": _mean(rows, m + "_ratio") for m in ("cnn", "released", "shipped")
                     if not rows or m in rows[0]}
            with open(out, "w") as f:
                json.dump({"rows": rows} | means, f, indent=1)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
