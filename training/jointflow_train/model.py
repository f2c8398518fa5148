"""The TFF network (paper Sec. 3.2 "Model", Fig. 3b): five 7x7 convolutions with stride 1 followed
by two 1x1 convolutions, ReLU after each but the last (the output holds unit-vector components,
which must be able to be negative).

Input: features(t-1) [C], beliefs(t-1) [17], features(t) [C], beliefs(t) [17] (the TFF contract in
models/README.md); output: 34 channels, 2j = x, 2j+1 = y of joint j, on the input grid.

`grid_stride` 2 runs the seven layers on a 2x coarser grid (average pooling in, a fixed bilinear
x2 upsampling out, both inside the graph) to meet a run-time budget; 1 is the paper's network.
"""
from __future__ import annotations

import torch
from torch import nn

NUM_JOINTS = 17


def bilinear_up2_kernel(channels: int) -> torch.Tensor:
    """Depthwise ConvTranspose (k=4, s=2) weights of half-pixel bilinear x2 upsampling."""
    k1 = torch.tensor([0.25, 0.75, 0.75, 0.25])
    return torch.outer(k1, k1).expand(channels, 1, 4, 4).clone()


class TFFNet(nn.Module):
    def __init__(self, feature_channels: int = 24, width: int = 32, grid_stride: int = 1):
        super().__init__()
        if grid_stride not in (1, 2):
            raise ValueError(f"grid_stride must be 1 or 2, got {grid_stride}")
        self.feature_channels = feature_channels
        self.width = width
        self.grid_stride = grid_stride
        in_ch = 2 * (feature_channels + NUM_JOINTS)
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

    def config(self) -> dict:
        return dict(feature_channels=self.feature_channels, width=self.width, grid_stride=self.grid_stride)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        if self.grid_stride == 1:
            return self.body(x)
        return self.up(self.pad(self.body(self.down(x))))


def masked_l2_loss(pred: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """Paper Eq. 5: sum_j sum_p M(p) * ||T*_j(p) - T_j(p)||^2, here averaged over the batch.

    mask: [B, 17, H, W] (per joint; the paper's M is the same for all joints, a per-joint mask
    also lets a person's unreliable joint be ignored alone) or [B, 1, H, W].
    """
    b = pred.shape[0]
    d2 = (pred - target).pow(2).view(b, NUM_JOINTS, 2, *pred.shape[2:]).sum(2)
    return (mask * d2).sum() / b
