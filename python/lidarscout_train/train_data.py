"""Reader for `lidarscout train-data` files, with numpy only.

Layout (see src/pipelines/training_data.hpp): a 48-byte preamble ("LSTRAIN1", then five
little-endian uint64: records_offset, record_size, count, meta_offset, meta_length), `count`
fixed-size records described by the JSON metadata's "fields", and the JSON metadata itself.

    python3 -m lidarscout_train.train_data FILE     # prints a JSON summary
"""
import json
import struct
import sys

import numpy as np

MAGIC = b"LSTRAIN1"


def load(path):
    """Returns (records, meta): a read-only numpy structured memmap with one entry per sample
    (fields height_in, rgb_in, height_gt, rgb_gt, mask, has_rgb, split) and the metadata dict."""
    with open(path, "rb") as f:
        head = f.read(48)
        if len(head) < 48 or head[:8] != MAGIC:
            raise ValueError(f"{path}: not a lidarscout training data file")
        records_offset, record_size, count, meta_offset, meta_length = struct.unpack("<5Q", head[8:48])
        f.seek(meta_offset)
        meta = json.loads(f.read(meta_length).decode("utf-8"))
    dtype = np.dtype([(name, kind, tuple(shape)) for name, kind, shape in meta["fields"]])
    if dtype.itemsize != record_size:
        raise ValueError(f"{path}: record size {record_size} does not match the fields ({dtype.itemsize})")
    if count == 0:
        return np.zeros(0, dtype=dtype), meta
    records = np.memmap(path, dtype=dtype, mode="r", offset=records_offset, shape=(count,))
    return records, meta


def summary(path):
    records, meta = load(path)
    out = {"count": int(len(records)), "record_size": int(records.dtype.itemsize), "fields": {}}
    for name in records.dtype.names:
        out["fields"][name] = list(records.dtype[name].shape)
    if len(records):
        gt = records["height_gt"].astype(np.float32)
        out["mask_sum"] = int(records["mask"].astype(np.int64).sum())
        out["gt_finite"] = int(np.isfinite(gt).sum())
        out["has_rgb"] = [int(v) for v in records["has_rgb"]]
        out["split"] = [int(v) for v in records["split"]]
        out["height_in_finite"] = bool(np.isfinite(records["height_in"].astype(np.float32)).all())
        out["first_sample"] = meta["samples"][0]
        out["linear_abs_max"] = float(np.abs(records["height_in"][:, 1].astype(np.float32)).max())
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python3 -m lidarscout_train.train_data FILE")
    print(json.dumps(summary(sys.argv[1])))
