"""Trains the heightmap network on a `lidarscout train-data` file and exports it to TorchScript.

    python3 -m lidarscout_train.train DATA.bin [MORE.bin ...] --out DIR [--epochs N] [--batch 32]
        [--decoder transposed|upsample] [--width 16] [--head-kernel 9] [--no-residual]
        [--threads 2] [--device cpu|cuda] [--lr 1e-4] [--milestones E,E] [--seed 1] [--no-augment] [--max-steps N]
        [--init state_dict.pt|model.pt] [--resume] [--max-per-file N]

Several train-data files are trained on together (their train splits, weighted as one set);
validation runs on all their held-out splits. --init starts from a saved state dict (its
decoder / width / head kernel / residual override the flags) or from a TorchScript model.pt
(the flags must then name its architecture; a mismatch fails): fine-tuning. Every epoch ends with
DIR/checkpoint.pt (weights, optimiser, schedule, history); --resume continues from it.

On a GPU machine (PyTorch 2.x with CUDA there) train with --device cuda and bring back
state_dict.pt; export it to TorchScript here with `python3 -m lidarscout_train.export`, so that
the file matches this machine's LibTorch (1.13).

Recipe (after the paper): AdamW (lr 1e-4, eps 1e-5, weight decay 1e-2), MultiStepLR x0.1 at
1/3 and 2/3 of the epochs; loss = MSE over texels with ground truth: height where mask (and the
ground truth is finite), colour where mask and the survey has colour; height loss + colour
loss; the height error of each sample is weighted so that every texel size counts alike
(dataset.set_texel_weights; --no-texel-weights for the plain MSE). Colour predictions are clipped to [0, 1] inside the model (as the reference); height
predictions are not clipped (normalised heights are not bounded: steep terrain in a small
window exceeds 1), the height error is used as is. Validation runs on the file's held-out
regions (split 1) without augmentation and reports the loss and the height RMSE in metres
(h' * radius_m of each sample, over texels with ground truth) and colour PSNR (peak 1), and
for comparison the height RMSE of the linearly interpolated input (h_lin) itself.

Writes to DIR: history.json (per-epoch figures), state_dict.pt (weights + model config) and
model.pt (TorchScript, traced; input float32 [B, 8, 96, 96] with NaN already replaced, output
[B, 4, 64, 64]; see model.py).
"""
import argparse
import json
import math
import os
import time
import warnings

import torch

from .dataset import TrainDataset, set_texel_weights
from .model import PAD, PATCH, HeightmapNet, count_parameters


def masked_losses(pred, batch):
    """Returns (total, height_mse, rgb_mse) averaged over the valid texels of the batch; the
    height error of each sample is scaled by its weight (batch["weight"], default 1)."""
    mh = batch["mask_h"]
    dh = (pred[:, 0] - batch["height"]) ** 2
    if "weight" in batch:
        dh = dh * batch["weight"].view(-1, 1, 1)
    lh = (dh * mh).sum() / mh.sum().clamp(min=1.0)
    lc = colour_mse(pred, batch)
    return lh + lc, lh, lc


def colour_mse(pred, batch):
    """The colour MSE averaged over the valid colour texels (and channels) of the batch."""
    mc = batch["mask_rgb"]
    dc = ((pred[:, 1:4] - batch["rgb"]) ** 2).sum(dim=1)
    return (dc * mc).sum() / (3.0 * mc.sum()).clamp(min=1.0)


def to_device(batch, device):
    return {k: v.to(device, non_blocking=True) for k, v in batch.items()}


def evaluate(model, loader, device="cpu"):
    """Mean loss per batch and height RMSE in metres / colour PSNR over all valid texels."""
    model.eval()
    total, batches, sq_m, n_h, sq_c, n_c, sq_lin = 0.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0
    with torch.no_grad():
        for batch in loader:
            batch = to_device(batch, device)
            pred = model(batch["x"])
            loss, _, _ = masked_losses(pred, batch)
            total += float(loss)
            batches += 1
            r = batch["radius"].view(-1, 1, 1)
            sq_m += float((((pred[:, 0] - batch["height"]) * r) ** 2 * batch["mask_h"]).sum())
            n_h += float(batch["mask_h"].sum())
            lin = batch["x"][:, 1, PAD:PAD + PATCH, PAD:PAD + PATCH]
            sq_lin += float((((lin - batch["height"]) * r) ** 2 * batch["mask_h"]).sum())
            sq_c += float((((pred[:, 1:4] - batch["rgb"]) ** 2).sum(dim=1) * batch["mask_rgb"]).sum())
            n_c += 3.0 * float(batch["mask_rgb"].sum())
    out = {"loss": total / max(batches, 1)}
    out["height_rmse_m"] = math.sqrt(sq_m / n_h) if n_h else None
    out["linear_height_rmse_m"] = math.sqrt(sq_lin / n_h) if n_h else None  # the h_lin input as is
    out["rgb_psnr_db"] = (10.0 * math.log10(1.0 / (sq_c / n_c)) if sq_c > 0 else None) if n_c else None
    return out


def export_torchscript(model, path, example=None):
    """Traces the model (eval mode, CPU) and saves it; returns the traced module."""
    model = model.eval()
    if example is None:
        example = torch.zeros(1, 8, 96, 96)
    with torch.no_grad():
        traced = torch.jit.trace(model, example)
    traced.save(path)
    return traced


def load_init(path, args):
    """The weights to fine-tune from: a state_dict.pt of this script (its decoder / width / head
    kernel / residual then override the flags in args) or a TorchScript model.pt (e.g. the
    shipped models/heightmap_cnn.pt; the flags must name its architecture)."""
    with warnings.catch_warnings():  # torch.load dispatches a TorchScript archive to torch.jit.load, with a warning
        warnings.simplefilter("ignore", UserWarning)
        init = torch.load(path, map_location="cpu")
    if isinstance(init, torch.jit.ScriptModule):
        return init.state_dict()
    args.decoder, args.width, args.head_kernel = init["decoder"], init["width"], init["head_kernel"]
    args.no_residual = not init.get("residual", True)
    return init["state_dict"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="+", help="train-data files")
    ap.add_argument("--out", required=True)
    ap.add_argument("--epochs", type=int, default=75)
    ap.add_argument("--batch", type=int, default=32)
    ap.add_argument("--decoder", choices=("transposed", "upsample"), default="transposed")
    ap.add_argument("--width", type=int, default=16)
    ap.add_argument("--head-kernel", type=int, default=9, help="kernel of the three final convolutions")
    ap.add_argument("--no-residual", action="store_true", help="the paper's plain heads (no correction of h_lin)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--device", default="cpu", help="cpu, or cuda on a GPU machine")
    ap.add_argument("--lr", type=float, default=1e-4)
    ap.add_argument("--milestones", help="epochs after which the lr drops x0.1, comma-separated (default: 1/3 and 2/3)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-augment", action="store_true")
    ap.add_argument("--max-steps", type=int, default=0, help="stop each epoch after N steps (smoke runs)")
    ap.add_argument("--init", help="state_dict.pt or TorchScript model.pt to start from (fine-tuning)")
    ap.add_argument("--resume", action="store_true", help="continue from DIR/checkpoint.pt when it exists")
    ap.add_argument("--max-per-file", type=int, default=0,
                    help="at most N training samples of each file (a random subset; 0: all)")
    ap.add_argument("--no-texel-weights", action="store_true",
                    help="plain MSE over normalised heights (the coarse texel sizes then weigh ~100x less)")
    args = ap.parse_args(argv)

    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    os.makedirs(args.out, exist_ok=True)

    train_parts = [TrainDataset(p, split="train", augment=not args.no_augment, seed=args.seed + k)
                   for k, p in enumerate(args.data)]
    if args.max_per_file:
        for k, part in enumerate(train_parts):
            part.limit(args.max_per_file, args.seed + k)
    train_set = torch.utils.data.ConcatDataset(train_parts)
    val_set = torch.utils.data.ConcatDataset([TrainDataset(p, split="validation", augment=False) for p in args.data])
    if len(train_set) == 0:
        raise SystemExit(f"{', '.join(args.data)}: no training samples")
    texel_weights = {} if args.no_texel_weights else set_texel_weights(train_parts)
    if texel_weights:
        print("height loss weight per texel size: " + ", ".join(f"{t:g} m: {w:.3g}" for t, w in sorted(texel_weights.items())),
              flush=True)
    gen = torch.Generator().manual_seed(args.seed)
    train_loader = torch.utils.data.DataLoader(train_set, batch_size=args.batch, shuffle=True, generator=gen, drop_last=False)
    val_loader = torch.utils.data.DataLoader(val_set, batch_size=args.batch, shuffle=False)

    init = load_init(args.init, args) if args.init else None
    model = HeightmapNet(decoder=args.decoder, width=args.width, head_kernel=args.head_kernel,
                         residual=not args.no_residual)
    if init is not None:
        model.load_state_dict(init)  # strict: a TorchScript file of another architecture fails here
    model = model.to(args.device)
    n_params = count_parameters(model)
    print(f"model: decoder={args.decoder} width={args.width} parameters={n_params}; "
          f"train {len(train_set)} validation {len(val_set)} samples", flush=True)
    opt = torch.optim.AdamW(model.parameters(), lr=args.lr, eps=1e-5, weight_decay=1e-2)
    milestones = (sorted(int(m) for m in args.milestones.split(",")) if args.milestones else
                  sorted({max(1, round(args.epochs / 3)), max(1, round(2 * args.epochs / 3))}))
    sched = torch.optim.lr_scheduler.MultiStepLR(opt, milestones=milestones, gamma=0.1)

    history = {"config": vars(args) | {"parameters": n_params, "milestones": milestones,
                                       "texel_weights": {str(k): v for k, v in texel_weights.items()}}, "epochs": []}
    ckpt_path = os.path.join(args.out, "checkpoint.pt")
    first = 0
    if args.resume and os.path.exists(ckpt_path):
        ckpt = torch.load(ckpt_path, map_location=args.device)
        model.load_state_dict(ckpt["model"])
        opt.load_state_dict(ckpt["opt"])
        sched.load_state_dict(ckpt["sched"])
        history["epochs"], first = ckpt["history_epochs"], ckpt["epoch"]
        gen.manual_seed(args.seed + first)
        print(f"resumed from {ckpt_path} after epoch {first}", flush=True)
    for epoch in range(first, args.epochs):
        model.train()
        t0 = time.time()
        total, lh_sum, lc_sum, steps = 0.0, 0.0, 0.0, 0
        for batch in train_loader:
            batch = to_device(batch, args.device)
            pred = model(batch["x"])
            loss, lh, lc = masked_losses(pred, batch)
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
            total += loss.item()
            lh_sum += lh.item()
            lc_sum += lc.item()
            steps += 1
            if args.max_steps and steps >= args.max_steps:
                break
        lr_used = opt.param_groups[0]["lr"]
        sched.step()
        rec = {"epoch": epoch + 1, "lr": lr_used, "train_loss": total / steps,
               "train_height_mse": lh_sum / steps, "train_rgb_mse": lc_sum / steps,
               "seconds": round(time.time() - t0, 2)}
        if len(val_set):
            v = evaluate(model, val_loader, args.device)
            rec |= {"val_loss": v["loss"], "val_height_rmse_m": v["height_rmse_m"], "val_rgb_psnr_db": v["rgb_psnr_db"],
                    "val_linear_height_rmse_m": v["linear_height_rmse_m"]}
        history["epochs"].append(rec)
        print(json.dumps(rec), flush=True)
        with open(os.path.join(args.out, "history.json"), "w") as f:
            json.dump(history, f, indent=1)
        torch.save({"model": model.state_dict(), "opt": opt.state_dict(), "sched": sched.state_dict(),
                    "history_epochs": history["epochs"], "epoch": epoch + 1}, ckpt_path + ".tmp")
        os.replace(ckpt_path + ".tmp", ckpt_path)

    model = model.cpu()
    torch.save({"state_dict": model.state_dict(), "decoder": args.decoder, "width": args.width,
                "head_kernel": args.head_kernel, "residual": not args.no_residual},
               os.path.join(args.out, "state_dict.pt"))
    export_torchscript(model, os.path.join(args.out, "model.pt"))
    print(f"wrote {args.out}/state_dict.pt, {args.out}/model.pt", flush=True)


if __name__ == "__main__":
    main()
