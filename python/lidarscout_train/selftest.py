"""Fast self-test of the training code (no data file needed; a few seconds on 2 CPU threads).

    python3 -m lidarscout_train.selftest       # prints "ok" on success, exits non-zero otherwise

Builds both decoder variants, checks output shapes, parameter counts and the colour clip, the
NaN replacement, the flip/rotation alignment of window and patch, checks that the untrained
residual network returns its linear inputs and that the cropped head equals the paper's padded
one, runs one training step on a tiny synthetic batch (the loss must be finite and the weights
must change), and exports to TorchScript, reloads it and compares its output with the eager
model.
"""
import io
import math
import sys

import numpy as np
import torch

from .batch_augment import BatchAugment
from .dataset import augment_colour, augment_geometry
from .fast_train import group_weights, learning_rate, parse_run, plan, window_rmse
from .window_pack import decode, encode, from_ordered, to_ordered
from .model import PAD, PATCH, HeightmapNet, count_parameters, replace_nan
from .train import masked_losses

EXPECTED_PARAMETERS = 2572132  # default width 16, both decoders


def synthetic_batch(b, gen):
    x = torch.rand(b, 8, 96, 96, generator=gen)
    x[:, 0:2] = x[:, 0:2] * 0.2 - 0.1
    mask = (torch.rand(b, 64, 64, generator=gen) > 0.2).float()
    return {
        "x": x,
        # Targets differ from the linear inputs, so that even the residual network at its
        # zero start has something to learn.
        "height": x[:, 1, PAD:PAD + PATCH, PAD:PAD + PATCH] + 0.05 * torch.sin(torch.arange(64.0) / 5.0),
        "rgb": (x[:, 5:8, PAD:PAD + PATCH, PAD:PAD + PATCH] * 0.9 + 0.05).clone(),
        "mask_h": mask,
        "mask_rgb": mask * torch.tensor([1.0] + [0.0] * (b - 1)).view(b, 1, 1),
        "radius": torch.full((b,), 480.0),
    }


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def check_relief_scale(gen):
    """A relief-scaled network's height correction scales with the window's heights: the same
    window at a tenth of the relief gets a tenth of the correction, and a flat window none."""
    net = HeightmapNet(decoder="upsample", width=4, head_kernel=5, relief_scale=True)
    with torch.no_grad():
        for p in net.parameters():  # random weights: the zero-started heads would make no correction
            p.copy_(torch.randn(p.shape, generator=gen) * 0.1)
    xb = replace_nan(synthetic_batch(1, gen)["x"])
    lin = xb[:, 1:2, PAD:PAD + PATCH, PAD:PAD + PATCH]
    with torch.no_grad():
        full = net(xb)[:, 0:1] - lin
        small = xb.clone()
        small[:, 0:2] *= 0.1
        tenth = net(small)[:, 0:1] - 0.1 * lin
        flat = xb.clone()
        flat[:, 0:2] = 0.0
        none = net(flat)[:, 0:1]
    check(float(full.abs().max()) > 0, "relief scale: the test network makes no correction")
    check(float((tenth - 0.1 * full).abs().max()) < 1e-5 * float(full.abs().max()) + 1e-7, "relief scale: not linear")
    check(float(none.abs().max()) < 1e-2 * float(full.abs().max()), "relief scale: a flat window got relief")


def check_batch_augment():
    """The batched augmentation equals dataset.py's per-sample flips, z-scale and colour change."""
    aug = BatchAugment("cpu", 3)
    x, tgt = torch.rand(5, 8, 96, 96), torch.rand(5, 6, 64, 64)
    has = torch.tensor([True, False, True, True, False])
    params = aug.draw(5)
    got_x, got_t = aug.apply(x, tgt, has, *params)
    t, s, gain, gc, o = params
    check(len(set(t.tolist())) > 1, "batch augment: one transform for every sample")
    for i in range(5):
        k, flip = int(t[i]) // 2, bool(int(t[i]) % 2)
        xi, ti = augment_geometry(x[i].numpy(), k, flip), augment_geometry(tgt[i].numpy(), k, flip)
        xi[0:2] *= float(s[i])
        ti[0] *= float(s[i])
        if has[i]:
            scale = np.tile(gc[i].numpy() * float(gain[i]), 2).reshape(-1, 1, 1)
            xi[2:8] = np.clip(xi[2:8] * scale + float(o[i]), 0, 1)
            ti[1:4] = np.clip(ti[1:4] * scale[:3] + float(o[i]), 0, 1)
        check(float(np.abs(got_x[i].numpy() - xi).max()) < 1e-6, f"batch augment: window {i}")
        check(float(np.abs(got_t[i].numpy() - ti).max()) < 1e-6, f"batch augment: target {i}")


def check_window_pack():
    """Packing is lossless: float16 (NaN and signs included) and 8-bit rows come back bit for bit."""
    h = np.array([[0.0, -0.0, 1.5, -2.25, np.nan, 65504.0, -1e-4, 3e-3]], dtype=np.float16)
    back = from_ordered(decode(encode(to_ordered(h))))
    check(np.array_equal(back.view(np.uint16), h.view(np.uint16)), "window_pack float16 round trip")
    check(bool(np.all(np.diff(to_ordered(np.array([-2, -1, 0, 1, 2], dtype=np.float16)).astype(int)) > 0)),
          "window_pack: ordered integers keep the float order")
    c = np.random.default_rng(1).integers(0, 256, size=(2, 3, 5), dtype=np.uint8)
    check(np.array_equal(decode(encode(c)), c), "window_pack uint8 round trip")


def check_fast_train_rules():
    """The clock's learning rate: warm-up, peak, decay to 1% at the deadline; group weights; run names."""
    check(learning_rate(1.0, 0.0) == 0.0 and abs(learning_rate(1.0, 0.03) - 1.0) < 1e-2, "lr warm-up")
    check(abs(learning_rate(1.0, 1.0) - 0.01) < 1e-9 and learning_rate(1.0, 0.5) < learning_rate(1.0, 0.2), "lr decay")
    w = group_weights(np.array([0, 0, 1, 1]), np.array([1.0, 1.0, 0.01, 0.01], dtype=np.float32))
    check(w[2] == 10.0 and w[0] < 1.0 and w[2] > w[0], f"group weights {w}")
    check(parse_run("shipped-unweighted-fold-a-b") == {"size": "shipped", "bf16": False, "weighted": False,
                                                       "scaled": False, "loss": "mse", "no1m": False, "seed": None,
                                                       "time_fraction": 1.0, "held_out": "a-b"},
          "run name with dashes")
    check(parse_run("shipped-scaled-rmse-fold-rmse-x") == {"size": "shipped", "bf16": False, "weighted": True,
                                                           "scaled": True, "loss": "rmse", "no1m": False,
                                                           "seed": None, "time_fraction": 1.0, "held_out": "rmse-x"},
          "rmse run name")
    control = parse_run("shipped-scaled-rmse-no1m-s2-fold-x")
    check(control["no1m"] is True and control["seed"] == 2 and control["loss"] == "rmse", f"control run {control}")
    check(parse_run("shipped-scaled-rmse-quarter-final")["time_fraction"] == 0.25, "quarter-length run name")
    runs = plan({"surveys": ["a", "b"]})
    check(len(runs) == 9 and "shipped-scaled-rmse-half-fold-b" in runs and "shipped-scaled-rmse-quarter-final" in runs
          and sorted(parse_run(r)["time_fraction"] for r in runs)[::3] == [0.25, 0.5, 1.0]
          and all(parse_run(r)["loss"] == "rmse" for r in runs), f"plan {runs}")
    # The per-window RMSE loss: a window's RMSE over its valid texels, weighed, averaged over windows.
    pred, height = torch.zeros(2, 2, 2), torch.tensor([[[3.0, 4.0], [9.0, 9.0]], [[1.0, 1.0], [1.0, 1.0]]])
    mask = torch.tensor([[[1.0, 1.0], [0.0, 0.0]], [[0.0, 0.0], [0.0, 0.0]]])
    got = float(window_rmse(pred, height, mask, torch.tensor([2.0, 5.0])))
    check(abs(got - 2.0 * math.sqrt(12.5) / 2) < 1e-5, f"window_rmse {got}")
    check(parse_run("shipped-scaled-final")["scaled"] is True, "relief-scaled run name")
    check(parse_run("shipped-bf16-final")["bf16"] is True, "bf16 run name")


def main():
    torch.set_num_threads(2)
    gen = torch.Generator().manual_seed(0)
    torch.manual_seed(0)

    # NaN replacement: 0 for heights, 0.5 for colours.
    x = torch.full((1, 8, 2, 2), float("nan"))
    y = replace_nan(x)
    check(bool((y[:, :2] == 0).all()) and bool((y[:, 2:] == 0.5).all()), "replace_nan")

    # A flip/rotation applied to the window and to the patch keeps them aligned.
    win = np.arange(96 * 96, dtype=np.float32).reshape(1, 96, 96)
    for k in range(4):
        for flip in (False, True):
            a = augment_geometry(win, k, flip)[:, PAD:PAD + PATCH, PAD:PAD + PATCH]
            b = augment_geometry(win[:, PAD:PAD + PATCH, PAD:PAD + PATCH], k, flip)
            check(np.array_equal(a, b), f"augment_geometry k={k} flip={flip}")

    # A colour change maps equal colours of the input window and the target to equal colours,
    # keeps missing texels missing and stays in [0, 1].
    rng = np.random.default_rng(3)
    c_in = np.full((6, 4, 4), 0.4, dtype=np.float32)
    c_in[:, 0, 0] = np.nan
    c_gt = np.full((3, 2, 2), 0.4, dtype=np.float32)
    changed_in, changed_gt = augment_colour([c_in, c_gt], rng, gain=(1.5, 1.6))
    check(np.isnan(changed_in[:, 0, 0]).all(), "augment_colour keeps NaN")
    check(np.allclose(changed_in[0:3, 1, 1], changed_gt[:, 0, 0]) and np.allclose(changed_in[3:6, 1, 1], changed_gt[:, 0, 0]),
          "augment_colour: the same change for inputs and target")
    check(not np.allclose(changed_gt, c_gt) and float(np.nanmax(changed_in)) <= 1.0, "augment_colour changes colours within [0, 1]")

    check_batch_augment()
    check_window_pack()
    check_fast_train_rules()

    # The residual network starts as linear interpolation; the padded ('same') and the
    # cropped ('valid') head agree on the centre.
    xb = replace_nan(synthetic_batch(2, gen)["x"])
    with torch.no_grad():
        start = HeightmapNet(decoder="upsample", width=4, head_kernel=5)(xb)
    centre = xb[:, :, PAD:PAD + PATCH, PAD:PAD + PATCH]
    check(bool(torch.equal(start[:, 0], centre[:, 1])), "untrained residual height != h_lin")
    check(bool(torch.equal(start[:, 1:], centre[:, 5:8].clamp(0, 1))), "untrained residual colour != linear colour")
    head = HeightmapNet(decoder="upsample", width=4).head_h
    hx = torch.randn(1, head.net[0].in_channels, 96, 96, generator=gen)
    ref = hx
    for layer in head.net:
        ref = torch.nn.functional.conv2d(ref, layer.weight, layer.bias, padding=4) if isinstance(layer, torch.nn.Conv2d) else torch.relu(ref)
    with torch.no_grad():
        check(float((head(hx) - ref[:, :, PAD:PAD + PATCH, PAD:PAD + PATCH]).abs().max()) < 1e-5, "valid head != padded head")
    check_relief_scale(gen)

    for kind in ("transposed", "upsample"):
        model = HeightmapNet(decoder=kind)
        n = count_parameters(model)
        check(n == EXPECTED_PARAMETERS, f"{kind}: {n} parameters, expected {EXPECTED_PARAMETERS}")
        small = HeightmapNet(decoder=kind, width=4, head_kernel=5)
        batch = synthetic_batch(2, gen)
        out = small(batch["x"])
        check(tuple(out.shape) == (2, 4, 64, 64), f"{kind}: output shape {tuple(out.shape)}")
        check(bool((out[:, 1:] >= 0).all() and (out[:, 1:] <= 1).all()), f"{kind}: colour not in [0, 1]")

        # One training step.
        opt = torch.optim.AdamW(small.parameters(), lr=1e-4, eps=1e-5, weight_decay=1e-2)
        before = [p.detach().clone() for p in small.parameters()]
        small.train()
        loss, _, _ = masked_losses(small(batch["x"]), batch)
        check(bool(torch.isfinite(loss)), f"{kind}: loss {float(loss)}")
        opt.zero_grad()
        loss.backward()
        opt.step()
        changed = sum(int(not torch.equal(a, p)) for a, p in zip(before, small.parameters()))
        check(changed > 0, f"{kind}: no weight changed")
        check(float(small.head_h.net[-1].weight.abs().sum()) > 0, f"{kind}: the zero-started height head got no gradient")

        # TorchScript export and reload (default width, as shipped).
        model.eval()
        with torch.no_grad():
            traced = torch.jit.trace(model, torch.zeros(1, 8, 96, 96))
        buf = io.BytesIO()
        torch.jit.save(traced, buf)
        buf.seek(0)
        loaded = torch.jit.load(buf)
        xb = replace_nan(synthetic_batch(3, gen)["x"])
        with torch.no_grad():
            ref = model(xb)
            got = loaded(xb)
        check(tuple(got.shape) == (3, 4, 64, 64), f"{kind}: TorchScript output shape {tuple(got.shape)}")
        diff = float((ref - got).abs().max())
        check(diff < 1e-5, f"{kind}: TorchScript differs from eager by {diff}")
    print("ok")


if __name__ == "__main__":
    try:
        main()
    except AssertionError as e:
        print(f"FAILED: {e}")
        sys.exit(1)
