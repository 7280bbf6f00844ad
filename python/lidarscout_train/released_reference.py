"""Writes a stand-in for the paper's released height network with the same interface (forward
takes a dict {"patch_hm_nearest", "patch_hm_linear"} of [n, 1, 96, 96] and returns the centre
[n, 1, 64, 64]) whose output is predictable: the linear input's centre crop times 1.5 (the
released model works in units 1.5 x its input's, so through the conventions of
src/nn/released_model.hpp it returns our linear heights unchanged). For the C++ test of those
conventions.

    python3 -m lidarscout_train.released_reference OUT.pt
"""
import sys
from typing import Dict

import torch


class LinearCrop(torch.nn.Module):
    def forward(self, batch: Dict[str, torch.Tensor]) -> torch.Tensor:
        lin = batch["patch_hm_linear"]
        return lin[:, :, 16:80, 16:80] * 1.5 + 0.0 * batch["patch_hm_nearest"][:, :, 16:80, 16:80]


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python3 -m lidarscout_train.released_reference OUT.pt")
    torch.jit.script(LinearCrop()).save(sys.argv[1])
