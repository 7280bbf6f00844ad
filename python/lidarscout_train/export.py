"""Exports a trained state dict (train.py's state_dict.pt, e.g. brought back from a GPU machine)
to TorchScript with this machine's torch, for the C++ side's LibTorch.

    python3 -m lidarscout_train.export STATE_DICT.pt OUT.pt
"""
import argparse

import torch

from .model import HeightmapNet
from .train import export_torchscript


def load_model(path):
    """The HeightmapNet of a state_dict.pt written by train.py, in eval mode on the CPU."""
    saved = torch.load(path, map_location="cpu")
    model = HeightmapNet(decoder=saved["decoder"], width=saved["width"], head_kernel=saved.get("head_kernel", 9),
                         residual=saved.get("residual", False), relief_scale=saved.get("relief_scale", False))
    model.load_state_dict(saved["state_dict"])
    return model.eval()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("state_dict")
    ap.add_argument("out")
    args = ap.parse_args(argv)
    export_torchscript(load_model(args.state_dict), args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
