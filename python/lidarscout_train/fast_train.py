"""Trains heightmap networks within a wall-clock deadline, the data held on the device (issue 35: the
leave-one-survey-out folds and the final model in one GPU run of at most 8 minutes).

    python3 -m lidarscout_train.fast_train plan WINDOWS [--tiny]
        the run names for the unpacked windows (window_pack unpack): shipped-scaled-rmse-fold-SURVEY
        for every survey and shipped-scaled-rmse-final (the shipped network: relief-scaled heights,
        model.py, the per-window RMSE loss below), once over the whole time and once over a quarter
        and a half of it (-quarter-, -half-: the schedule ends early, its decay included), since the
        second GPU run's ky-jmo335 fold scored 0.997 of linear after 2,900 steps and 0.918-0.929
        after 600 (models/README.md): the folds choose the schedule's length. Names parse as
        SIZE[-scaled][-bf16][-unweighted][-rmse][-no1m][-s2][-quarter|-half]-(final|fold-SURVEY):
        without -rmse- the pooled MSE of the first GPU run (worse in every row of the second), and
        what earlier runs settled and the plan leaves out: the plain network (without -scaled-),
        bf16, texel-size weights (-unweighted-), 1 m windows left out (-no1m-), seed 2 (-s2-).
        --tiny: two runs (a fold with the pooled MSE, the final model with the RMSE loss).
        The paper size ("paper": width 16, 9 x 9 heads) trains too when named, but is not planned:
        it costs 21 ms per patch at batch 16 on 2 cores (models/README.md), five times the 4 ms budget.
    python3 -m lidarscout_train.fast_train train WINDOWS --run NAME --out DIR --deadline UNIX_TIME
        [--device cuda|cpu] [--seed 1] [--tiny]
        one run until the deadline; DIR/checkpoint.pt every epoch (a rerun resumes from it),
        DIR/state.pt (float16 weights) and DIR/history.json at the end
    python3 -m lidarscout_train.fast_train bundle RUNS --out DIR
        every run's state.pt into DIR/models-K.pt files of at most 15 MiB, histories in DIR/histories.json
    python3 -m lidarscout_train.fast_train unbundle DIR --out RUNS
        back on this machine: RUNS/NAME/state_dict.pt (train.py's format), model.pt (TorchScript
        with this machine's torch) and history.json for every run in DIR's bundles

The recipe: the windows of every source but the fold's survey; per step a random batch of them
(an epoch is one pass in random order), augmented on the device (batch_augment.py: flips and
rotations, z-scale 0.3..2, colour); AdamW (eps 1e-5, weight decay 1e-2) at a learning rate that
follows the clock: a linear warm-up over the first 3% of the time given, then a cosine decay to
1% of the peak at the deadline, so the decay always happens inside the time there is; float32
(the first GPU run trained in bf16 autocast: on its float32 comparison fold bf16 cost 0.004-0.014
of the ratio to linear for 4% more steps, so runs named -bf16- only use it).

The loss is train.py's masked MSE, each window weighed by its group (one train-data file at one
texel size: one source, one density): the median of the groups' mean linear-interpolation errors
over that of its group. Every group then counts by how much better than linear the network does on
it, as the evaluation does (a ratio to linear per survey), so that a flat survey, where linear
interpolation is already close and any invented relief costs a large ratio, weighs as much as a
steep one (issue 35, item 3: flat ground left flat). The weights are clipped to [0.1, 10].
Runs named -rmse- optimise what the evaluation measures, the mean over windows of each window's
height RMSE: each window's RMSE weighed by the median group's mean linear RMSE over its group's
(pooled MSE lets the windows with the largest errors dominate within a group; with a per-window
RMSE a dense window, whose linear error is small, counts as much as a sparse one).
"""
import argparse
import contextlib
import json
import math
import os
import sys
import time

import numpy as np
import torch

from .batch_augment import BatchAugment
from .model import PAD, PATCH, RGB_FILL, HeightmapNet, count_parameters
from .train import colour_mse, export_torchscript, masked_losses

SIZES = {
    "shipped": {"decoder": "upsample", "width": 8, "head_kernel": 5, "lr": 4e-4},
    "paper": {"decoder": "upsample", "width": 16, "head_kernel": 9, "lr": 2e-4},
}
BATCH = 64
WARMUP = 0.03
FINAL_LR = 0.01
Z_RANGE = (0.3, 2.0)
WEIGHT_CLIP = (0.1, 10.0)
BUNDLE_BYTES = 15 * 1024 * 1024


def plan(meta, tiny=False):
    surveys = meta["surveys"]
    if tiny:
        return [f"shipped-scaled-fold-{surveys[0]}", "shipped-scaled-rmse-final"]
    return [f"shipped-scaled{variant}-{kind}" for variant in ("-rmse", "-rmse-quarter", "-rmse-half")
            for kind in [f"fold-{s}" for s in surveys] + ["final"]]


def parse_run(name):
    """{size, bf16, weighted, scaled, loss (mse or rmse), no1m, seed (None: --seed), time_fraction (of the
    time to the deadline), held_out (a survey or None)} of a run name (see plan in the docstring)."""
    size, rest = name.split("-", 1)
    if size not in SIZES:
        raise SystemExit(f"{name}: unknown size {size!r} (one of {', '.join(SIZES)})")
    run = {"size": size, "bf16": False, "weighted": True, "scaled": False, "loss": "mse", "no1m": False,
           "seed": None, "time_fraction": 1.0, "held_out": None}
    for flag, key, value in (("scaled-", "scaled", True), ("bf16-", "bf16", True), ("unweighted-", "weighted", False),
                             ("rmse-", "loss", "rmse"), ("no1m-", "no1m", True), ("s2-", "seed", 2),
                             ("quarter-", "time_fraction", 0.25), ("half-", "time_fraction", 0.5)):
        if rest.startswith(flag):
            run[key], rest = value, rest[len(flag):]
    if rest == "final":
        return run
    if not rest.startswith("fold-"):
        raise SystemExit(f"{name}: expected SIZE[-scaled][-bf16][-unweighted][-rmse][-no1m][-s2][-quarter|-half]-"
                         "(final|fold-SURVEY)")
    return run | {"held_out": rest[len("fold-"):]}


def load_meta(folder):
    with open(os.path.join(folder, "meta.json")) as f:
        return json.load(f)


def to_tensors(folder, rows, device, chunk=512):
    """x [N, 8, 96, 96] and target [N, 6, 64, 64] (height, r, g, b, mask_h, mask_rgb) in float16 on
    the device, NaN replaced as dataset.py does, and has_rgb [N] bool."""
    a = {k: np.load(os.path.join(folder, k + ".npy"), mmap_mode="r")
         for k in ("height_in", "rgb_in", "height_gt", "rgb_gt", "mask", "has_rgb")}
    n = len(rows)
    x = torch.empty((n, 8, 96, 96), dtype=torch.float16, device=device)
    tgt = torch.empty((n, 6, 64, 64), dtype=torch.float16, device=device)
    for lo in range(0, n, chunk):
        r = rows[lo:lo + chunk]
        has = a["has_rgb"][r].astype(bool)
        h_in = np.nan_to_num(a["height_in"][r].astype(np.float32), nan=0.0)
        c_in = np.where(has[:, None, None, None], a["rgb_in"][r].astype(np.float32) / 255.0, RGB_FILL)
        gt = a["height_gt"][r].astype(np.float32)
        mask_h = (a["mask"][r] != 0) & np.isfinite(gt)
        rgb = a["rgb_gt"][r].astype(np.float32) / 255.0
        t = np.concatenate([np.where(mask_h, gt, 0.0)[:, None], rgb, mask_h[:, None],
                            (mask_h & has[:, None, None])[:, None]], axis=1)
        x[lo:lo + len(r)] = torch.from_numpy(np.concatenate([h_in, c_in], axis=1)).to(device, torch.float16)
        tgt[lo:lo + len(r)] = torch.from_numpy(t.astype(np.float32)).to(device, torch.float16)
    has_rgb = torch.from_numpy(a["has_rgb"][rows].astype(bool)).to(device)
    return x, tgt, has_rgb


def group_weights(groups, lin_error):
    """Per window: the median over groups of their mean linear error (MSE, or RMSE for -rmse- runs) /
    that of its group, clipped (see the docstring; the median, so that the clip bounds the flattest
    and the steepest groups alike)."""
    ok = np.isfinite(lin_error)
    means = {g: float(np.mean(lin_error[(groups == g) & ok])) for g in np.unique(groups)
             if ((groups == g) & ok).any()}
    reference = float(np.median([m for m in means.values() if m > 0])) if means else 1.0
    w = np.ones(len(groups), dtype=np.float32)
    for g, m in means.items():
        if m > 0:
            w[groups == g] = reference / m
    return np.clip(w, *WEIGHT_CLIP)


def weighted_loss(pred, tgt, weight, loss="mse"):
    """train.masked_losses (weighted height MSE + colour MSE over valid texels) of a packed target; with
    loss "rmse" the height term is the weighted mean of the windows' own RMSEs instead (the colour
    term stays)."""
    batch = {"height": tgt[:, 0], "rgb": tgt[:, 1:4], "mask_h": tgt[:, 4], "mask_rgb": tgt[:, 5], "weight": weight}
    if loss == "mse":
        return masked_losses(pred, batch)[0]
    return window_rmse(pred[:, 0], tgt[:, 0], tgt[:, 4], weight) + colour_mse(pred, batch)


def window_rmse(pred_h, height, mask, weight):
    """The mean over windows of weight x the window's height RMSE over its valid texels (a window
    without one adds nothing)."""
    n = mask.sum(dim=(1, 2))
    mse = (((pred_h - height) ** 2) * mask).sum(dim=(1, 2)) / n.clamp(min=1.0)
    return (weight * torch.sqrt(mse + 1e-12) * (n > 0)).mean()


def learning_rate(peak, frac):
    warm = min(1.0, frac / WARMUP) if WARMUP > 0 else 1.0
    frac = min(max(frac, 0.0), 1.0)
    return peak * warm * (FINAL_LR + (1.0 - FINAL_LR) * 0.5 * (1.0 + math.cos(math.pi * frac)))


def heldout_figures(model, x, tgt, radius, texel, density, device, bf16, batch=64):
    """Per (texel, density): windows, mean per-window height RMSE (m) of the network and of the
    linear input, and their ratio (as `lidarscout eval` reports it per survey)."""
    model.eval()
    rmse_cnn, rmse_lin = [], []
    with torch.no_grad():
        for lo in range(0, len(x), batch):
            xb, tb = x[lo:lo + batch].float(), tgt[lo:lo + batch].float()
            with autocast(bf16):
                pred = model(xb)
            r = radius[lo:lo + batch].view(-1, 1, 1)
            m = tb[:, 4]
            lin = xb[:, 1, PAD:PAD + PATCH, PAD:PAD + PATCH]
            n = m.sum(dim=(1, 2)).clamp(min=1.0)
            rmse_cnn.append(torch.sqrt((((pred[:, 0].float() - tb[:, 0]) * r) ** 2 * m).sum(dim=(1, 2)) / n))
            rmse_lin.append(torch.sqrt((((lin - tb[:, 0]) * r) ** 2 * m).sum(dim=(1, 2)) / n))
    rc, rl = torch.cat(rmse_cnn).cpu().numpy(), torch.cat(rmse_lin).cpu().numpy()
    out = []
    for t, d in sorted(set(zip(texel.tolist(), density.tolist()))):
        sel = (texel == t) & (density == d)
        cnn, lin = float(rc[sel].mean()), float(rl[sel].mean())
        out.append({"texel_m": t, "density": d, "windows": int(sel.sum()), "cnn_rmse_m": cnn, "linear_rmse_m": lin,
                    "ratio": cnn / lin if lin > 0 else None})
    model.train()
    return out


def autocast(bf16):
    """bf16 autocast on CUDA, or nothing (torch 1.13 on a CPU cannot even build a disabled CUDA autocast)."""
    return torch.autocast(device_type="cuda", dtype=torch.bfloat16) if bf16 else contextlib.nullcontext()


def save_atomic(obj, path):
    torch.save(obj, path + ".tmp")
    os.replace(path + ".tmp", path)


class Fold:
    """The windows of one run on the device: training (every source but the held-out survey) and
    held-out (that survey's windows, for the figures in the history)."""

    def __init__(self, windows, held, device, weighted, loss, tiny, no1m=False):
        meta = load_meta(windows)
        source = np.load(os.path.join(windows, "source.npy"))
        held_id = meta["sources"].index(held) if held is not None else -1
        texel = np.load(os.path.join(windows, "texel_m.npy"))
        keep = source != held_id
        if no1m:
            keep &= texel != 1.0
        rows = np.nonzero(keep)[0]
        self.x, self.tgt, self.has_rgb = to_tensors(windows, rows, device)
        lin_mse = np.load(os.path.join(windows, "lin_mse.npy"))[rows]
        groups = np.load(os.path.join(windows, "group.npy" if weighted else "texel_m.npy"))[rows]
        lin_error = lin_mse if loss == "mse" else np.sqrt(np.maximum(lin_mse, 0.0))  # NaN stays NaN
        self.weight = torch.from_numpy(group_weights(groups, lin_error)).to(device)
        self.n = len(rows)
        self.held = None
        if held is not None:
            hrows = np.nonzero(source == held_id)[0][:32 if tiny else None]
            hx, ht, _ = to_tensors(windows, hrows, device)
            radius = torch.from_numpy(np.load(os.path.join(windows, "radius_m.npy"))[hrows]).to(device)
            self.held = (hx, ht, radius, texel[hrows],
                         np.load(os.path.join(windows, "density.npy"))[hrows])

    def figures(self, model, device, bf16):
        return None if self.held is None else heldout_figures(model, *self.held, device, bf16)


def save_state(model, cfg, run, name, path):
    """The float16 weights and the configuration export.load_model needs."""
    save_atomic({"state_dict": {k: v.detach().cpu().half() for k, v in model.state_dict().items()},
                 "decoder": cfg["decoder"], "width": cfg["width"], "head_kernel": cfg["head_kernel"],
                 "residual": True, "relief_scale": run["scaled"], "run": name}, path)


def train_epoch(model, opt, aug, fold, perm, batch, bf16, peak_lr, clock, first, loss_kind):
    """One pass over perm (or until clock() reaches 1; the first epoch of a run makes at least one
    step, however late it starts); returns (steps, last lr, loss sum tensor)."""
    loss_sum, steps, lr = torch.zeros((), device=fold.x.device), 0, 0.0
    for k in range(max(1, fold.n // batch)):
        frac = clock()
        if frac >= 1.0 and not (first and k == 0):
            break
        lr = learning_rate(peak_lr, frac)
        for g in opt.param_groups:
            g["lr"] = lr
        idx = perm[k * batch:(k + 1) * batch]
        xb, tb = aug(fold.x[idx].float(), fold.tgt[idx].float(), fold.has_rgb[idx])
        with autocast(bf16):
            pred = model(xb)
        loss = weighted_loss(pred.float(), tb, fold.weight[idx], loss_kind)
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        loss_sum += loss.detach()
        steps += 1
    return steps, lr, loss_sum


def train(args):
    run = parse_run(args.run)
    began = time.time()
    deadline = began + run["time_fraction"] * (args.deadline - began)  # a -quarter- or -half- run ends early
    cfg, held = SIZES[run["size"]], run["held_out"]
    device = args.device
    bf16 = run["bf16"] and device.startswith("cuda")
    seed = run["seed"] if run["seed"] is not None else args.seed
    torch.manual_seed(seed)
    torch.set_num_threads(1)
    torch.backends.cudnn.benchmark = True
    os.makedirs(args.out, exist_ok=True)
    batch = 8 if args.tiny else BATCH
    t_load = time.time()
    fold = Fold(args.windows, held, device, run["weighted"], run["loss"], args.tiny, run["no1m"])
    model = HeightmapNet(decoder=cfg["decoder"], width=cfg["width"], head_kernel=cfg["head_kernel"],
                         relief_scale=run["scaled"]).to(device)
    extra = {"fused": True} if device.startswith("cuda") else {}
    opt = torch.optim.AdamW(model.parameters(), lr=cfg["lr"], eps=1e-5, weight_decay=1e-2, **extra)
    aug = BatchAugment(device, seed, z_range=Z_RANGE)
    perm_gen = torch.Generator(device=device)
    perm_gen.manual_seed(seed)
    history = {"run": args.run, "config": cfg | {"batch": batch, "bf16": bf16, "held_out": held, "windows": fold.n,
                                                 "weights": "group" if run["weighted"] else "texel",
                                                 "relief_scale": run["scaled"], "loss": run["loss"],
                                                 "parameters": count_parameters(model), "z_range": Z_RANGE,
                                                 "warmup": WARMUP, "final_lr": FINAL_LR,
                                                 "weight_clip": WEIGHT_CLIP, "seed": seed,
                                                 "no_1m_windows": run["no1m"],
                                                 "time_fraction": run["time_fraction"]},
               "load_seconds": round(time.time() - t_load, 2), "epochs": []}
    ckpt, state_path = os.path.join(args.out, "checkpoint.pt"), os.path.join(args.out, "state.pt")
    used = 0.0
    if os.path.exists(ckpt):
        c = torch.load(ckpt, map_location=device)
        model.load_state_dict(c["model"])
        opt.load_state_dict(c["opt"])
        aug.gen.set_state(c["aug_gen"])
        perm_gen.set_state(c["perm_gen"])
        history["epochs"], used = c["epochs"], c["seconds"]
        print(f"{args.run}: resumed after {len(history['epochs'])} epochs, {used:.0f} s", flush=True)
    print(f"{args.run}: {fold.n} windows, {history['config']['parameters']} parameters, bf16 {bf16}, "
          f"loaded in {history['load_seconds']} s", flush=True)

    start = time.time()
    reserve = 5.0 if held is None else 12.0  # the held-out figures and saving
    total = used + max(1.0, deadline - reserve - start)
    clock = lambda: (used + time.time() - start) / total  # noqa: E731
    while True:
        t_epoch = time.time()
        perm = torch.randperm(fold.n, generator=perm_gen, device=device)
        steps, lr, loss_sum = train_epoch(model, opt, aug, fold, perm, batch, bf16, cfg["lr"], clock,
                                          first=not history["epochs"], loss_kind=run["loss"])
        if steps == 0:
            break
        history["epochs"].append({"epoch": len(history["epochs"]) + 1, "steps": steps, "lr_end": lr,
                                  "train_loss": float(loss_sum) / steps, "seconds": round(time.time() - t_epoch, 3)})
        save_atomic({"model": model.state_dict(), "opt": opt.state_dict(), "aug_gen": aug.gen.get_state(),
                     "perm_gen": perm_gen.get_state(), "epochs": history["epochs"],
                     "seconds": used + time.time() - start}, ckpt)
        if len(history["epochs"]) == 1:  # the end's paths early (a failure there shows in seconds, not minutes)
            history["held_out_epoch1"] = fold.figures(model, device, bf16)
            save_state(model, cfg, run, args.run, state_path)
    seconds = used + time.time() - start
    steps = sum(e["steps"] for e in history["epochs"])
    history |= {"train_seconds": round(seconds, 2), "steps": steps,
                "windows_per_second": round(steps * batch / max(seconds, 1e-9), 1)}
    save_state(model, cfg, run, args.run, state_path)
    history["held_out"] = fold.figures(model, device, bf16)
    with open(os.path.join(args.out, "history.json"), "w") as f:
        json.dump(history, f, indent=1)
    print(json.dumps({k: history[k] for k in ("run", "steps", "train_seconds", "windows_per_second")} |
                     {"held_out": history.get("held_out")}), flush=True)


def bundle(runs_dir, out):
    os.makedirs(out, exist_ok=True)
    names = sorted(d for d in os.listdir(runs_dir) if os.path.exists(os.path.join(runs_dir, d, "state.pt")))
    bundles, current, current_bytes, histories = [], {}, 0, {}
    for name in names:
        state = torch.load(os.path.join(runs_dir, name, "state.pt"), map_location="cpu")
        nbytes = sum(v.numel() * v.element_size() for v in state["state_dict"].values()) + 64 * 1024
        if current and current_bytes + nbytes > BUNDLE_BYTES:
            bundles.append(current)
            current, current_bytes = {}, 0
        current[name] = state
        current_bytes += nbytes
        with open(os.path.join(runs_dir, name, "history.json")) as f:
            histories[name] = json.load(f)
    if current:
        bundles.append(current)
    for k, b in enumerate(bundles):
        torch.save(b, os.path.join(out, f"models-{k}.pt"))
    with open(os.path.join(out, "histories.json"), "w") as f:
        json.dump(histories, f, indent=1)
    print(f"{out}: {len(names)} runs in {len(bundles)} bundle(s)")


def unbundle(folder, out):
    from .export import load_model
    with open(os.path.join(folder, "histories.json")) as f:
        histories = json.load(f)
    count = 0
    for fname in sorted(os.listdir(folder)):
        if not (fname.startswith("models-") and fname.endswith(".pt")):
            continue
        for name, state in torch.load(os.path.join(folder, fname), map_location="cpu").items():
            run = os.path.join(out, name)
            os.makedirs(run, exist_ok=True)
            state = dict(state, state_dict={k: v.float() for k, v in state["state_dict"].items()})
            torch.save(state, os.path.join(run, "state_dict.pt"))
            export_torchscript(load_model(os.path.join(run, "state_dict.pt")), os.path.join(run, "model.pt"))
            with open(os.path.join(run, "history.json"), "w") as f:
                json.dump(histories.get(name, {}), f, indent=1)
            count += 1
    print(f"{out}: {count} runs exported")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("plan")
    p.add_argument("windows")
    p.add_argument("--tiny", action="store_true")
    t = sub.add_parser("train")
    t.add_argument("windows")
    t.add_argument("--run", required=True)
    t.add_argument("--out", required=True)
    t.add_argument("--deadline", type=float, required=True, help="Unix time at which the run must be over")
    t.add_argument("--device", default="cuda")
    t.add_argument("--seed", type=int, default=1)
    t.add_argument("--tiny", action="store_true", help="batch 8 and 32 held-out windows (an end-to-end check)")
    b = sub.add_parser("bundle")
    b.add_argument("runs")
    b.add_argument("--out", required=True)
    u = sub.add_parser("unbundle")
    u.add_argument("folder")
    u.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    if args.cmd == "plan":
        print(" ".join(plan(load_meta(args.windows), args.tiny)))
    elif args.cmd == "train":
        train(args)
    elif args.cmd == "bundle":
        bundle(args.runs, args.out)
    else:
        unbundle(args.folder, args.out)


if __name__ == "__main__":
    sys.exit(main())
