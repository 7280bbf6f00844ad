"""Packs training windows of `lidarscout train-data` files into one xz file small enough to send to
a GPU machine (at most 64 MiB travel there), and unpacks them there into plain .npy arrays.

    python3 -m lidarscout_train.window_pack pack FILE.bin... --out windows.xz [--per-group N]
        [--surveys NAME,NAME...] [--seed 1]
    python3 -m lidarscout_train.window_pack unpack windows.xz DIR

A group is one (file, texel size); each keeps a random N of its windows (seeded by the group's
name, so a rebuild picks the same ones). The source of a window is its file's name up to the
first dot (`scripts/train_gpu.sh data` names them SOURCE.cpN.bin and SOURCE.fine.bin); --surveys
names the sources that are leave-one-survey-out folds (the others are extra training data, in
every fold). Nothing is lost: float16 heights are mapped to ordered 16-bit integers and, like the
8-bit colours and masks, stored as differences along each row (smooth rasters become runs of
small numbers that xz compresses well); unpack inverts both exactly.

Unpacked arrays (DIR/NAME.npy, one row per window): height_in f2 [2,96,96], rgb_in u1 [6,96,96],
height_gt f2 [64,64], rgb_gt u1 [3,64,64], mask u1 [64,64], has_rgb u1, texel_m f4, radius_m f4,
source i2, group i2, density i4 (chunk points per window of a .cpN file, 0 otherwise), lin_mse f4
(the linear input's MSE against the ground truth, normalised units); DIR/meta.json: sources,
surveys, groups.
"""
import argparse
import io
import json
import lzma
import os
import re
import sys
import zlib

import numpy as np

from .dataset import linear_mse
from .train_data import load

IMAGE_FIELDS = ("height_in", "rgb_in", "height_gt", "rgb_gt", "mask")


def to_ordered(a):
    """float16 -> uint16 whose integer order is the float order (NaN bits kept)."""
    u = a.view(np.uint16)
    return np.where(u & 0x8000, ~u, u | 0x8000).astype(np.uint16)


def from_ordered(o):
    """Inverse of to_ordered."""
    u = np.where(o & 0x8000, o & 0x7FFF, ~o).astype(np.uint16)
    return u.view(np.float16)


def encode(a):
    """Row differences (along the last axis, wrapping) of an unsigned array."""
    d = a.copy()
    d[..., 1:] = a[..., 1:] - a[..., :-1]
    return d


def decode(d):
    return np.cumsum(d, axis=-1, dtype=d.dtype)


def source_of(path):
    return os.path.basename(path).split(".")[0]


def density_of(path):
    m = re.search(r"\.cp(\d+)\.bin$", path)
    return int(m.group(1)) if m else 0


def select(paths, per_group, seed):
    """[(path, group name, record indices)] with at most per_group windows per (file, texel)."""
    chosen = []
    for path in paths:
        records, meta = load(path)
        texels = np.array([s["texel_m"] for s in meta.get("samples", [])], dtype=np.float32)
        for t in np.unique(texels):
            idx = np.nonzero(texels == t)[0]
            name = f"{os.path.basename(path)}@{t:g}m"
            if len(idx) > per_group:
                rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
                idx = np.sort(rng.choice(idx, size=per_group, replace=False))
            chosen.append((path, name, idx))
    return chosen


def gather(chosen, surveys):
    """The arrays of the chosen windows and the metadata."""
    sources = sorted({source_of(p) for p, _, _ in chosen})
    cols = {k: [] for k in IMAGE_FIELDS + ("has_rgb", "texel_m", "radius_m", "source", "group", "density", "lin_mse")}
    for g, (path, _, idx) in enumerate(chosen):
        records, meta = load(path)
        samples = meta["samples"]
        for i in idx:
            r = records[int(i)]
            for k in IMAGE_FIELDS:
                cols[k].append(np.asarray(r[k]))
            cols["has_rgb"].append(r["has_rgb"])
            cols["texel_m"].append(samples[int(i)]["texel_m"])
            cols["radius_m"].append(samples[int(i)]["radius_m"])
            cols["source"].append(sources.index(source_of(path)))
            cols["group"].append(g)
            cols["density"].append(density_of(path))
            cols["lin_mse"].append(linear_mse(r))
    kinds = {"has_rgb": np.uint8, "texel_m": np.float32, "radius_m": np.float32, "source": np.int16,
             "group": np.int16, "density": np.int32, "lin_mse": np.float32}
    arrays = {k: np.stack(v) if k in IMAGE_FIELDS else np.asarray(v, dtype=kinds[k]) for k, v in cols.items()}
    meta = {"sources": sources, "surveys": [s for s in surveys if s in sources],
            "groups": [name for _, name, _ in chosen]}
    return arrays, meta


def pack(paths, out, per_group, surveys, seed=1):
    chosen = select(paths, per_group, seed)
    arrays, meta = gather(chosen, surveys)
    stored = {}
    for k, a in arrays.items():
        if a.dtype == np.float16:
            a = encode(to_ordered(a))
        elif k in IMAGE_FIELDS:
            a = encode(a)
        stored[k] = a
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8), **stored)
    tmp = out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(lzma.compress(buf.getvalue(), preset=6))
    os.replace(tmp, out)
    return len(arrays["group"]), meta


def unpack(path, folder):
    with open(path, "rb") as f:
        z = np.load(io.BytesIO(lzma.decompress(f.read())))
    os.makedirs(folder, exist_ok=True)
    meta = json.loads(bytes(z["meta"]).decode())
    for k in z.files:
        if k == "meta":
            continue
        a = z[k]
        if k in ("height_in", "height_gt"):
            a = from_ordered(decode(a))
        elif k in IMAGE_FIELDS:
            a = decode(a)
        np.save(os.path.join(folder, k + ".npy"), a)
    with open(os.path.join(folder, "meta.json"), "w") as f:
        json.dump(meta, f)
    return meta


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("pack")
    p.add_argument("files", nargs="+")
    p.add_argument("--out", required=True)
    p.add_argument("--per-group", type=int, default=90)
    p.add_argument("--surveys", default="", help="comma-separated sources that are LOSO folds")
    p.add_argument("--seed", type=int, default=1)
    u = sub.add_parser("unpack")
    u.add_argument("file")
    u.add_argument("folder")
    args = ap.parse_args(argv)
    if args.cmd == "pack":
        n, meta = pack(args.files, args.out, args.per_group, [s for s in args.surveys.split(",") if s], args.seed)
        print(f"{args.out}: {n} windows of {len(meta['sources'])} sources ({len(meta['surveys'])} folds), "
              f"{len(meta['groups'])} groups, {os.path.getsize(args.out)} bytes")
    else:
        meta = unpack(args.file, args.folder)
        print(f"{args.folder}: {len(meta['groups'])} groups of {len(meta['sources'])} sources")


if __name__ == "__main__":
    sys.exit(main())
