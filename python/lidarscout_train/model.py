"""The heightmap network: four 96 x 96 input images of a patch window -> 64 x 64 height and colour.

This module is the one place that defines the network's tensor interface (the C++ inference
side must follow it):

  input  float32 [B, 8, 96, 96], channels in this order
           0  h_nn    nearest-neighbour height          (normalised, h' = (z - centre_z) / radius_m)
           1  h_lin   linearly interpolated height      (normalised)
           2  r_nn    nearest-neighbour red             (0..1 = 8-bit value / 255)
           3  g_nn    nearest-neighbour green
           4  b_nn    nearest-neighbour blue
           5  r_lin   linearly interpolated red
           6  g_lin   linearly interpolated green
           7  b_lin   linearly interpolated blue
         NaN replacement (done by the caller before the network, see `replace_nan`): a NaN height
         becomes 0.0, a NaN colour (and every colour of a survey without colour) becomes 0.5.
  output float32 [B, 4, 64, 64]: channel 0 height (normalised like the inputs, not clipped),
         channels 1..3 r, g, b in [0, 1] (clipped); the centre 64 x 64 of the 96 x 96 window.
         Back to metres: z = centre_z + h' * radius_m (see src/recon/patch_space.hpp).

Architecture (after the paper's description, written from scratch):
  - one encoder per input image (h_nn 1 ch, h_lin 1 ch, rgb_nn 3 ch, rgb_lin 3 ch): four 3 x 3
    convolutions with stride 3 (96 -> 32 -> 10 -> 3 -> 1), ReLU after each, giving a feature
    vector per input (channels 2w, 4w, 8w, 8w; w = width = 16 by default);
  - fully connected merge of the four concatenated vectors (one linear layer + ReLU), then per
    output (height, colour) one more linear layer + ReLU to that decoder's start vector;
  - one decoder per output back to 96 x 96 (1 -> 3 -> 10 -> 32 -> 96): either transposed 3 x 3
    convolutions with stride 3 ("transposed", as the paper) or nearest upsampling to the next
    size followed by a 3 x 3 convolution ("upsample"; same parameter count, faster in LibTorch
    on CPU);
  - skip concat of the decoder features with all eight raw inputs, then three 9 x 9
    convolutions (padding 4) per output (`head_kernel` makes them smaller in cheaper variants);
  - residual outputs (`residual=True`, our addition): the height head predicts a correction to
    the linearly interpolated height h_lin, the colour head one to the linear colour, and the
    last convolution of each head starts at zero, so an untrained network returns linear
    interpolation and training only has to learn what linear gets wrong. (The paper's
    network has to rebuild the height from the skip inputs; with our small training set this
    converges much faster and never falls behind linear interpolation on flat ground.)
  - relief scaling (`relief_scale=True`, our addition, issue 35): the heights enter the network
    divided by the window's relief (the standard deviation of h_lin over the window, at least
    RELIEF_FLOOR) and the height correction leaves it multiplied by the same, so the correction
    scales with the relief the chunk points show: a window with no relief gets none, whatever
    the network learned on steep terrain;
  - crop to the centre 64 x 64 (16 texels of padding on each side).
"""
import torch
import torch.nn as nn
import torch.nn.functional as F

CHANNELS = ("h_nn", "h_lin", "r_nn", "g_nn", "b_nn", "r_lin", "g_lin", "b_lin")
OUTPUTS = ("height", "r", "g", "b")
WINDOW = 96
PATCH = 64
PAD = (WINDOW - PATCH) // 2
HEIGHT_FILL = 0.0
RGB_FILL = 0.5
RELIEF_FLOOR = 1e-3  # normalised height (0.48 m at 10 m texels, radius 480 m)

# Sizes along the encoder (conv 3x3 stride 3, no padding) and back along the decoder.
_SIZES = (96, 32, 10, 3, 1)


def replace_nan(x):
    """x: [B, 8, H, W] float tensor; returns a copy with NaN heights -> 0 and NaN colours -> 0.5."""
    h = torch.nan_to_num(x[:, 0:2], nan=HEIGHT_FILL)
    c = torch.nan_to_num(x[:, 2:8], nan=RGB_FILL)
    return torch.cat([h, c], dim=1)


def count_parameters(model):
    """Number of trainable parameters."""
    return sum(p.numel() for p in model.parameters() if p.requires_grad)


class Encoder(nn.Module):
    """in_ch x 96 x 96 -> feature vector of channels[-1] (four 3x3 stride-3 convs, ReLU)."""

    def __init__(self, in_ch, channels):
        super().__init__()
        layers = []
        prev = in_ch
        for c in channels:
            layers += [nn.Conv2d(prev, c, 3, stride=3), nn.ReLU(inplace=True)]
            prev = c
        self.net = nn.Sequential(*layers)

    def forward(self, x):
        return torch.flatten(self.net(x), 1)  # [B, C, 1, 1] -> [B, C]


class Decoder(nn.Module):
    """feature vector [B, channels[0]] -> [B, channels[-1], 96, 96]; 1 -> 3 -> 10 -> 32 -> 96."""

    def __init__(self, channels, kind):
        super().__init__()
        if kind not in ("transposed", "upsample"):
            raise ValueError(f"unknown decoder kind {kind!r}")
        layers = []
        sizes = _SIZES[::-1]  # 1, 3, 10, 32, 96
        for k in range(len(channels) - 1):
            cin, cout, n_in, n_out = channels[k], channels[k + 1], sizes[k], sizes[k + 1]
            if kind == "transposed":
                # (n_in - 1) * 3 + 3 + output_padding = n_out
                op = n_out - 3 * n_in
                layers.append(nn.ConvTranspose2d(cin, cout, 3, stride=3, output_padding=op))
            else:
                layers.append(nn.Upsample(size=(n_out, n_out), mode="nearest"))
                layers.append(nn.Conv2d(cin, cout, 3, padding=1))
            layers.append(nn.ReLU(inplace=True))
        self.net = nn.Sequential(*layers)
        self.c0 = channels[0]

    def forward(self, v):
        return self.net(v.view(v.shape[0], self.c0, 1, 1))


class Head(nn.Module):
    """Skip concat (decoder features + raw inputs) -> three k x k convs -> out_ch maps of the
    centre 64 x 64.

    The paper pads each convolution ('same') and crops the 96 x 96 result; the centre 64 x 64
    of that never sees the padding (three convs reach 3 * (k // 2) texels <= 16), so the head
    crops its input to the texels the centre needs and runs unpadded ('valid') convolutions:
    the same function, with the same weights, at 40-60% of the cost."""

    def __init__(self, in_ch, mid, out_ch, kernel=9, zero_last=False):
        super().__init__()
        self.reach = 3 * (kernel // 2)
        if self.reach > PAD:
            raise ValueError(f"head kernel {kernel} reaches beyond the {PAD}-texel padding")
        self.net = nn.Sequential(
            nn.Conv2d(in_ch, mid, kernel), nn.ReLU(inplace=True),
            nn.Conv2d(mid, mid, kernel), nn.ReLU(inplace=True),
            nn.Conv2d(mid, out_ch, kernel),
        )
        if zero_last:
            nn.init.zeros_(self.net[-1].weight)
            nn.init.zeros_(self.net[-1].bias)

    def forward(self, x):
        lo = PAD - self.reach
        return self.net(x[:, :, lo:lo + PATCH + 2 * self.reach, lo:lo + PATCH + 2 * self.reach])


class HeightmapNet(nn.Module):
    """[B, 8, 96, 96] (NaN already replaced) -> [B, 4, 64, 64]; see the module docstring.

    width scales every channel count; the default (16) gives about 2.5 M parameters.
    head_kernel: size of the three final convolutions (9 as the paper). residual: see above."""

    def __init__(self, decoder="transposed", width=16, head_kernel=9, residual=True, relief_scale=False):
        super().__init__()
        w = width
        self.decoder_kind = decoder
        self.width = width
        self.head_kernel = head_kernel
        self.residual = residual
        self.relief_scale = relief_scale
        if relief_scale and not residual:
            raise ValueError("relief scaling scales the residual correction: it needs residual heads")
        enc = (2 * w, 4 * w, 8 * w, 8 * w)  # 32, 64, 128, 128
        feat = enc[-1]
        merged = 32 * w  # 512
        dec = (16 * w, 8 * w, 4 * w, 2 * w, w)  # 256 -> ... -> 16 channels at 96 x 96
        head_mid = 2 * w  # 32
        self.enc_h_nn = Encoder(1, enc)
        self.enc_h_lin = Encoder(1, enc)
        self.enc_rgb_nn = Encoder(3, enc)
        self.enc_rgb_lin = Encoder(3, enc)
        self.merge = nn.Sequential(
            nn.Linear(4 * feat, merged), nn.ReLU(inplace=True),
        )
        self.to_dec_h = nn.Sequential(nn.Linear(merged, dec[0]), nn.ReLU(inplace=True))
        self.to_dec_rgb = nn.Sequential(nn.Linear(merged, dec[0]), nn.ReLU(inplace=True))
        self.dec_h = Decoder(dec, decoder)
        self.dec_rgb = Decoder(dec, decoder)
        self.head_h = Head(dec[-1] + 8, head_mid, 1, head_kernel, zero_last=residual)
        self.head_rgb = Head(dec[-1] + 8, head_mid, 3, head_kernel, zero_last=residual)

    def forward(self, x):
        raw = x
        if self.relief_scale:
            relief = x[:, 1].flatten(1).std(dim=1).clamp(min=RELIEF_FLOOR).view(-1, 1, 1, 1)
            x = torch.cat([x[:, 0:2] / relief, x[:, 2:8]], dim=1)
        v = torch.cat([
            self.enc_h_nn(x[:, 0:1]),
            self.enc_h_lin(x[:, 1:2]),
            self.enc_rgb_nn(x[:, 2:5]),
            self.enc_rgb_lin(x[:, 5:8]),
        ], dim=1)
        m = self.merge(v)
        fh = self.dec_h(self.to_dec_h(m))
        fc = self.dec_rgb(self.to_dec_rgb(m))
        h = self.head_h(torch.cat([fh, x], dim=1))
        c = self.head_rgb(torch.cat([fc, x], dim=1))
        if self.residual:
            centre = raw[:, :, PAD:PAD + PATCH, PAD:PAD + PATCH]
            if self.relief_scale:
                h = h * relief
            h = h + centre[:, 1:2]
            c = c + centre[:, 5:8]
        else:
            # Colour starts around mid-grey so that the [0, 1] clip does not cut the gradient at init.
            c = c + RGB_FILL
        return torch.cat([h, torch.clamp(c, 0.0, 1.0)], dim=1)


def layer_summary(model):
    """Lines 'name: parameters' per top-level child (for reports)."""
    return [f"{name}: {count_parameters(child)}" for name, child in model.named_children()]


if __name__ == "__main__":
    for kind, width, kernel in (("transposed", 16, 9), ("upsample", 16, 9), ("upsample", 8, 5)):
        m = HeightmapNet(kind, width, kernel)
        print(kind, width, kernel, count_parameters(m))
        for line in layer_summary(m):
            print("  ", line)
