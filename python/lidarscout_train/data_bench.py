"""Windows per second of the two training data paths on this machine's CPU (issue 35, item 2):
train.py's (dataset.TrainDataset through a DataLoader: per-sample numpy augmentation) against
fast_train.py's (the windows converted once at the start of a run, timed apart, then whole
batches augmented with torch operations). Only the data path is timed: no network step.

    python3 -m lidarscout_train.data_bench WINDOWS FILE.bin... [--batches 20] [--batch 64] [--runs 3]

WINDOWS: a folder of `window_pack unpack` (the batched path); FILE.bin: train-data files (the
per-sample path). Prints the median of the runs for each path, and their ratio.
"""
import argparse
import statistics
import time

import numpy as np
import torch

from .batch_augment import BatchAugment
from .dataset import TrainDataset
from .fast_train import to_tensors


def per_sample(files, batches, batch, seed):
    data = torch.utils.data.ConcatDataset([TrainDataset(p, split="train", augment=True, seed=seed) for p in files])
    gen = torch.Generator().manual_seed(seed)
    loader = torch.utils.data.DataLoader(data, batch_size=batch, shuffle=True, generator=gen, drop_last=True)
    t0, n = time.perf_counter(), 0
    for k, b in enumerate(loader):
        n += b["x"].shape[0]
        if k + 1 == batches:
            break
    return n / (time.perf_counter() - t0)


def batched(windows, batches, batch, seed):
    """(windows/s of the batches, seconds per window of the conversion a run does once at its start)."""
    rows = np.arange(batches * batch) % len(np.load(f"{windows}/source.npy"))
    t0 = time.perf_counter()
    x, tgt, has_rgb = to_tensors(windows, rows, "cpu")
    convert = (time.perf_counter() - t0) / len(rows)
    aug = BatchAugment("cpu", seed)
    gen = torch.Generator().manual_seed(seed)
    perm = torch.randperm(len(rows), generator=gen)
    t0 = time.perf_counter()
    for k in range(batches):
        idx = perm[k * batch:(k + 1) * batch]
        aug(x[idx].float(), tgt[idx].float(), has_rgb[idx])
    return batches * batch / (time.perf_counter() - t0), convert


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("windows")
    ap.add_argument("files", nargs="+")
    ap.add_argument("--batches", type=int, default=20)
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args(argv)
    torch.set_num_threads(1)
    before = statistics.median(per_sample(args.files, args.batches, args.batch, r) for r in range(args.runs))
    runs = [batched(args.windows, args.batches, args.batch, r) for r in range(args.runs)]
    after = statistics.median(r[0] for r in runs)
    convert = statistics.median(r[1] for r in runs)
    print(f"per-sample numpy (train.py): {before:.0f} windows/s; batched torch (fast_train.py): {after:.0f} windows/s "
          f"({after / before:.1f}x) after a conversion of {1000 * convert:.1f} ms per window once per run "
          f"(one thread, median of {args.runs} runs of {args.batches} batches of {args.batch})")


if __name__ == "__main__":
    main()
