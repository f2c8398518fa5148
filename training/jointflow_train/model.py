"""The TFF network (paper Sec. 3.2 "Model", Fig. 3b): five 7x7 convolutions with stride 1 followed
by two 1x1 convolutions, ReLU after each but the last (the output holds unit-vector components,
which must be able to be negative).

Input: features(t-1) [C], beliefs(t-1) [17], features(t) [C], beliefs(t) [17] (the TFF contract in
models/README.md); output: 34 channels, 2j = x, 2j+1 = y of joint j, on the input grid.

`grid_stride` 2 runs the seven layers on a 2x coarser grid (average pooling in, a fixed bilinear
x2 upsampling out) to meet a run-time budget; 1 is the paper's network. The export leaves the
pooling to the C++ runner (export.py, PooledInput).
"""
from __future__ import annotations

import torch
from torch import nn

NUM_JOINTS = 17


def bilinear_up2_kernel(channels: int) -> torch.Tensor:
    """Depthwise ConvTranspose (k=4, s=2) weights of half-pixel bilinear x2 upsampling."""
    k1 = torch.tensor([0.25, 0.75, 0.75, 0.25])
    return torch.outer(k1, k1).expand(channels, 1, 4, 4).clone()


class ChannelAffine(nn.Module):
    """x * weight + bias per channel (frozen). Exported as Mul + Add, which OpenCV 4.6 runs and
    which keeps the first Conv the 7x7 one, whose input channel count the C++ runner checks.
    Parameter shapes match a depthwise 1x1 Conv2d (weight [C, 1, 1, 1], bias [C])."""

    def __init__(self, channels: int):
        super().__init__()
        self.weight = nn.Parameter(torch.ones(channels, 1, 1, 1), requires_grad=False)
        self.bias = nn.Parameter(torch.zeros(channels), requires_grad=False)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x * self.weight.view(1, -1, 1, 1) + self.bias.view(1, -1, 1, 1)


class TFFNet(nn.Module):
    def __init__(self, feature_channels: int = 24, width: int = 32, grid_stride: int = 1):
        super().__init__()
        if grid_stride not in (1, 2):
            raise ValueError(f"grid_stride must be 1 or 2, got {grid_stride}")
        self.feature_channels = feature_channels
        self.width = width
        self.grid_stride = grid_stride
        in_ch = 2 * (feature_channels + NUM_JOINTS)
        # Per-channel input standardisation. The belief maps are mostly ~0 with small peaks and
        # the features have other scales; standardised inputs train much faster (measured: the
        # network without it still output ~0 after 450 steps; set_input_stats from training maps).
        self.norm = ChannelAffine(in_ch)
        layers = []
        for i in range(5):
            layers += [nn.Conv2d(in_ch if i == 0 else width, width, 7, padding=3), nn.ReLU(inplace=True)]
        layers += [nn.Conv2d(width, width, 1), nn.ReLU(inplace=True), nn.Conv2d(width, 2 * NUM_JOINTS, 1)]
        self.body = nn.Sequential(*layers)
        if grid_stride == 2:
            self.down = nn.AvgPool2d(2)
            # Edge padding + ConvTranspose(pad 3) equals half-pixel bilinear x2 exactly, borders
            # included (a form OpenCV 4.6 dnn runs; shared/notes/models.md).
            self.pad = nn.ReplicationPad2d(1)
            self.up = nn.ConvTranspose2d(2 * NUM_JOINTS, 2 * NUM_JOINTS, 4, stride=2, padding=3,
                                         groups=2 * NUM_JOINTS, bias=False)
            self.up.weight.data.copy_(bilinear_up2_kernel(2 * NUM_JOINTS))
            self.up.weight.requires_grad_(False)

    def set_input_stats(self, mean: torch.Tensor, std: torch.Tensor) -> None:
        """x -> (x - mean) / std per input channel."""
        std = std.clamp_min(1e-3)
        self.norm.weight.data.copy_((1 / std).view(-1, 1, 1, 1))
        self.norm.bias.data.copy_(-mean / std)

    def config(self) -> dict:
        return dict(feature_channels=self.feature_channels, width=self.width, grid_stride=self.grid_stride)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        x = self.norm(x)
        if self.grid_stride == 1:
            return self.body(x)
        return self.up(self.pad(self.body(self.down(x))))


def masked_l2_loss(pred: torch.Tensor, target: torch.Tensor, mask: torch.Tensor,
                   positive_weight: float = 1.0) -> torch.Tensor:
    """Paper Eq. 5: sum_j sum_p M(p) * ||T*_j(p) - T_j(p)||^2, here averaged over the batch.

    mask: [B, 17, H, W] (per joint; the paper's M is the same for all joints, a per-joint mask
    also lets a person's unreliable joint be ignored alone) or [B, 1, H, W].
    positive_weight: 1 is Eq. 5. Above 1, cells inside some Omega (non-zero target) weigh that
    much more. Measured here: with Eq. 5 as it stands, our pseudo-labelled pairs (motions mostly
    below one grid cell, ~0.1 % of the cells non-zero) train a network that outputs ~0 everywhere
    (training/README.md); the weight counters that imbalance.
    """
    b = pred.shape[0]
    d2 = (pred - target).pow(2).view(b, NUM_JOINTS, 2, *pred.shape[2:]).sum(2)
    if positive_weight != 1.0:
        inside = target.view(b, NUM_JOINTS, 2, *target.shape[2:]).abs().sum(2) > 0
        mask = mask * (1 + (positive_weight - 1) * inside.to(mask.dtype))
    return (mask * d2).sum() / b
