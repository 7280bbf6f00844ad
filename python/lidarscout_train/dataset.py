"""Torch Dataset over a `lidarscout train-data` file, with the training augmentations.

Each item is a dict of float32 tensors:
  x        [8, 96, 96]  network input (channel order and NaN replacement: see model.py)
  height   [64, 64]     normalised ground-truth height (0 where there is none)
  rgb      [3, 64, 64]  ground-truth colour in [0, 1]
  mask_h   [64, 64]     1 where the height ground truth exists (mask and finite)
  mask_rgb [64, 64]     mask_h, and 0 everywhere for a survey without colour
  radius   []           radius_m of the sample (normalised height * radius = metres)
  weight   []           the sample's weight in the height loss (1 unless set_texel_weights)
  index    []           record index in the file

Augmentation (train only, `augment=True`): a random one of the 8 flips / 90-degree rotations
applied identically to inputs and targets, and z-scale: normalised heights of inputs and
target multiplied by one random factor, log-uniform in [z_min, z_max] (0.5..2 by default);
colour (`colour_augment=True`): one random brightness/contrast change of the whole sample,
inputs and target alike (see augment_colour), so that the network corrects colours relative to
its inputs instead of pulling them toward the training surveys' mean (without it, a darker
survey never seen in training came out 0.12 brighter and 3-4 dB worse than linear).
"""
import math

import numpy as np
import torch

from .model import HEIGHT_FILL, PAD, PATCH, RGB_FILL
from .train_data import load

SPLIT_TRAIN = 0
SPLIT_VALIDATION = 1


class TrainDataset(torch.utils.data.Dataset):
    def __init__(self, path, split=None, augment=False, z_range=(0.5, 2.0), seed=None, colour_augment=None):
        """colour_augment: None = same as augment."""
        self.records, self.meta = load(path)
        if split == "train":
            split = SPLIT_TRAIN
        elif split in ("validation", "val"):
            split = SPLIT_VALIDATION
        if split is None:
            self.indices = np.arange(len(self.records))
        else:
            self.indices = np.nonzero(np.asarray(self.records["split"]) == split)[0] if len(self.records) else np.zeros(0, int)
        samples = self.meta.get("samples", [])
        self.radius = np.array([s["radius_m"] for s in samples], dtype=np.float32)
        self.texel = np.array([s["texel_m"] for s in samples], dtype=np.float32)
        self.weight = np.ones(len(samples), dtype=np.float32)
        self.augment = augment
        self.colour_augment = augment if colour_augment is None else colour_augment
        self.z_range = z_range
        self.rng = np.random.default_rng(seed)

    def limit(self, count, seed):
        """Keeps at most `count` of the selected samples, a random subset fixed by `seed` (so that
        one large file does not outweigh the others)."""
        if len(self.indices) > count:
            keep = np.random.default_rng(seed).choice(len(self.indices), size=count, replace=False)
            self.indices = self.indices[np.sort(keep)]

    def __len__(self):
        return len(self.indices)

    def __getitem__(self, i):
        idx = int(self.indices[i])
        r = self.records[idx]
        h_in = np.asarray(r["height_in"], dtype=np.float32)  # [2, 96, 96]
        has_rgb = bool(r["has_rgb"])
        if has_rgb:
            c_in = np.asarray(r["rgb_in"], dtype=np.float32) / 255.0  # [6, 96, 96]
        else:
            c_in = np.full((6,) + h_in.shape[1:], np.nan, dtype=np.float32)
        gt = np.asarray(r["height_gt"], dtype=np.float32)  # [64, 64]
        mask_h = (np.asarray(r["mask"]) != 0) & np.isfinite(gt)
        gt = np.where(mask_h, gt, 0.0)
        rgb = np.asarray(r["rgb_gt"], dtype=np.float32) / 255.0  # [3, 64, 64]
        if self.colour_augment and has_rgb:
            c_in, rgb = augment_colour([c_in, rgb], self.rng)
        h_in = np.where(np.isfinite(h_in), h_in, HEIGHT_FILL)
        c_in = np.where(np.isfinite(c_in), c_in, RGB_FILL)
        mask_rgb = mask_h & has_rgb

        x = np.concatenate([h_in, c_in], axis=0)
        tgt = np.concatenate([gt[None], rgb, mask_h[None].astype(np.float32), mask_rgb[None].astype(np.float32)], axis=0)
        if self.augment:
            k = int(self.rng.integers(4))
            flip = bool(self.rng.integers(2))
            x = augment_geometry(x, k, flip)
            tgt = augment_geometry(tgt, k, flip)
            lo, hi = self.z_range
            s = math.exp(self.rng.uniform(math.log(lo), math.log(hi)))
            x[0:2] *= s
            tgt[0] *= s
        return {
            "x": torch.from_numpy(np.ascontiguousarray(x, dtype=np.float32)),
            "height": torch.from_numpy(np.ascontiguousarray(tgt[0])),
            "rgb": torch.from_numpy(np.ascontiguousarray(tgt[1:4])),
            "mask_h": torch.from_numpy(np.ascontiguousarray(tgt[4])),
            "mask_rgb": torch.from_numpy(np.ascontiguousarray(tgt[5])),
            "radius": torch.tensor(float(self.radius[idx]) if len(self.radius) > idx else 1.0),
            "weight": torch.tensor(float(self.weight[idx]) if len(self.weight) > idx else 1.0),
            "index": torch.tensor(idx),
        }


def linear_mse(record):
    """Mean squared error (normalised units) of the linear input against the ground truth."""
    lin = np.asarray(record["height_in"][1], dtype=np.float32)[PAD:PAD + PATCH, PAD:PAD + PATCH]
    gt = np.asarray(record["height_gt"], dtype=np.float32)
    m = (np.asarray(record["mask"]) != 0) & np.isfinite(gt) & np.isfinite(lin)
    return float(np.mean((lin[m] - gt[m]) ** 2)) if m.any() else float("nan")


def set_texel_weights(datasets):
    """Weights every texel size equally in the height loss: a sample's weight is the mean
    linear-interpolation MSE over all samples divided by that of its texel size.

    Normalised heights shrink with the window (h' = z / radius), so without this the 10 m
    samples (radius 480 m) weigh ~100x less than the 1 m ones (radius 48 m) in a plain MSE
    and the network barely learns the coarse texels. `datasets`: one TrainDataset or a list
    (several train-data files weighted together). Returns {texel_m: weight}."""
    if isinstance(datasets, TrainDataset):
        datasets = [datasets]
    mse = np.array([linear_mse(d.records[int(i)]) for d in datasets for i in d.indices])
    tex = np.concatenate([d.texel[d.indices] for d in datasets]) if datasets else np.zeros(0)
    ok = np.isfinite(mse)
    overall = float(np.mean(mse[ok]))
    weights = {}
    for t in np.unique(tex):
        group = ok & (tex == t)
        weights[float(t)] = overall / float(np.mean(mse[group])) if group.any() else 1.0
    for d in datasets:
        for i in d.indices:
            d.weight[int(i)] = weights[float(d.texel[int(i)])]
    return weights


def augment_colour(arrays, rng, gain=(0.6, 1.6), channel_gain=(0.9, 1.1), offset=0.08):
    """The same random colour change applied to each array ([3k, H, W] colours in [0, 1],
    channels cycling r, g, b; NaN stays NaN): c' = clip(g * g_c * c + o, 0, 1) with one gain g
    (log-uniform in `gain`), a gain per channel g_c (log-uniform in `channel_gain`) and a shift o
    (uniform in +-offset)."""
    g = math.exp(rng.uniform(math.log(gain[0]), math.log(gain[1])))
    gc = np.exp(rng.uniform(math.log(channel_gain[0]), math.log(channel_gain[1]), size=3)).astype(np.float32)
    o = np.float32(rng.uniform(-offset, offset))
    out = []
    for a in arrays:
        scale = np.tile(gc * np.float32(g), a.shape[0] // 3).reshape(-1, 1, 1)
        out.append(np.clip(a * scale + o, 0.0, 1.0))  # NaN stays NaN through clip
    return out


def augment_geometry(a, k, flip):
    """a: [C, H, W]; rotate by k * 90 degrees in the image plane, then optionally mirror the columns.
    The same (k, flip) on the 96 x 96 window and the 64 x 64 centre patch keeps them aligned,
    because the patch is centred in the window."""
    a = np.rot90(a, k, axes=(1, 2))
    if flip:
        a = a[:, :, ::-1]
    return a.copy()
