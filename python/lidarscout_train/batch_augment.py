"""The training augmentations of dataset.py applied to whole batches with torch operations, on
whatever device the batch is on (the GPU's data path; dataset.py's per-sample numpy version
starved a GPU at about 150 windows per second).

Per sample, drawn from a torch.Generator (reproducible from its seed):
  - one of the 8 flips / 90-degree rotations, as dataset.augment_geometry, applied to the
    96 x 96 inputs and the 64 x 64 targets alike, by one gather through precomputed index maps;
  - z-scale: the normalised heights of inputs and target times one factor, log-uniform in z_range;
  - colour (samples with colour only): c' = clip(g * g_c * c + o, 0, 1) as dataset.augment_colour,
    inputs and target alike.
Heights must already have their NaN replaced (0 stays 0 under z-scale, as in dataset.py).
"""
import math

import numpy as np
import torch

from .dataset import augment_geometry


def geometry_maps(size, device):
    """[8, size * size] long: transform t = 2 * k + flip takes texel maps[t][i] of a raster to i."""
    grid = np.arange(size * size).reshape(1, size, size)
    maps = [augment_geometry(grid, k, flip).reshape(-1) for k in range(4) for flip in (False, True)]
    return torch.as_tensor(np.stack(maps), device=device)


def apply_geometry(a, maps, t):
    """a [B, C, H, W], maps [8, H * W], t [B] in 0..7 -> a transformed per sample."""
    b, c, h, w = a.shape
    index = maps[t].unsqueeze(1).expand(b, c, h * w)
    return a.reshape(b, c, h * w).gather(2, index).view(b, c, h, w)


def log_uniform(n, lo, hi, gen, device):
    u = torch.rand(n, generator=gen, device=device)
    return torch.exp(math.log(lo) + u * (math.log(hi) - math.log(lo)))


class BatchAugment:
    """augment(x, target) -> (x, target): x [B, 8, 96, 96] float, target [B, 6, 64, 64] float
    (height, r, g, b, mask_h, mask_rgb); has_rgb [B] bool marks the samples whose colours change."""

    def __init__(self, device, seed, z_range=(0.5, 2.0), gain=(0.6, 1.6), channel_gain=(0.9, 1.1), offset=0.08):
        self.gen = torch.Generator(device=device)
        self.gen.manual_seed(seed)
        self.device = device
        self.maps96 = geometry_maps(96, device)
        self.maps64 = geometry_maps(64, device)
        self.z_range, self.gain, self.channel_gain, self.offset = z_range, gain, channel_gain, offset

    def draw(self, b):
        """The random parameters of b samples: transform, z-scale, gain, per-channel gain, offset."""
        g, d = self.gen, self.device
        t = torch.randint(0, 8, (b,), generator=g, device=d)
        s = log_uniform(b, *self.z_range, g, d)
        gain = log_uniform(b, *self.gain, g, d)
        gc = log_uniform(3 * b, *self.channel_gain, g, d).view(b, 3)
        o = (torch.rand(b, generator=g, device=d) * 2 - 1) * self.offset
        return t, s, gain, gc, o

    def __call__(self, x, target, has_rgb):
        return self.apply(x, target, has_rgb, *self.draw(x.shape[0]))

    def apply(self, x, target, has_rgb, t, s, gain, gc, o):
        x = apply_geometry(x, self.maps96, t)
        target = apply_geometry(target, self.maps64, t)
        x = torch.cat([x[:, 0:2] * s.view(-1, 1, 1, 1), x[:, 2:8]], dim=1)
        scale = (gain.view(-1, 1) * gc).view(-1, 3, 1, 1)
        o = o.view(-1, 1, 1, 1)
        c_in = torch.clamp(x[:, 2:8] * scale.repeat(1, 2, 1, 1) + o, 0.0, 1.0)
        c_gt = torch.clamp(target[:, 1:4] * scale + o, 0.0, 1.0)
        keep = has_rgb.view(-1, 1, 1, 1)
        x = torch.cat([x[:, 0:2], torch.where(keep, c_in, x[:, 2:8])], dim=1)
        target = torch.cat([target[:, 0:1] * s.view(-1, 1, 1, 1), torch.where(keep, c_gt, target[:, 1:4]),
                            target[:, 4:6]], dim=1)
        return x, target
