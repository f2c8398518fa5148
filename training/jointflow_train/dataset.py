"""Training pairs from the cached maps (cache.py): input maps of frames t and t+s, the rendered
TFF target (paper Eq. 2-4) and the loss mask M (Eq. 5).

Augmentations (issue 6): frame strides s (default 1, 2, 3), mirrored frames (MoveNet run on the
mirrored image; its poses come with left/right already swapped), synthetic camera motion (frame
t+s warped by a random affine map before MoveNet, its poses carried through the same map), and
random crops of the grid (the network is fully convolutional).
"""
from __future__ import annotations

from typing import List, Sequence

import numpy as np

from .posetrack import UNMAPPED_JOINTS
from .pseudo_labels import associate, motions_and_mask
from .tff_render import render_tff

NUM_JOINTS = 17


class Video:
    def __init__(self, path: str):
        d = np.load(path)
        self.name = str(d["source"])
        self.maps = {v: d[f"{v}_maps"] for v in ("orig", "flip")}
        self.kps = {v: [d[f"{v}_kps"][i, :d[f"{v}_count"][i]] for i in range(len(d[f"{v}_count"]))]
                    for v in ("orig", "flip")}
        self.warp_t, self.warp_s, self.warp_flip = d["warp_t"], d["warp_s"], d["warp_flip"]
        self.warp_affine, self.warp_maps = d["warp_affine"], d["warp_maps"]
        # PoseTrack ground truth (posetrack.py): track ids, ignore regions; pseudo-labels have none.
        self.tracks = {v: d[f"{v}_track"] for v in ("orig", "flip")} if "orig_track" in d.files else None
        self.ignore = {v: d[f"{v}_ignore"] for v in ("orig", "flip")} if "orig_ignore" in d.files else None
        self.warp_ignore = d["warp_ignore"] if "warp_ignore" in d.files else None
        self.num_frames = len(self.kps["orig"])
        self.grid_hw = self.maps["orig"].shape[2:]


def transform_kps(kps: np.ndarray, affine: np.ndarray) -> np.ndarray:
    out = kps.copy()
    out[..., :2] = kps[..., :2] @ affine[:, :2].T + affine[:, 2]
    return out


class PairDataset:
    """entries: ("pair", video, variant, t, s) and ("warp", video, warp index)."""

    def __init__(self, files: Sequence[str], strides=(1, 2, 3), use_flips=True, use_warps=True,
                 sigma: float = 1.0):
        self.videos: List[Video] = [Video(f) for f in files]
        self.sigma = sigma
        self.entries = []
        for vi, v in enumerate(self.videos):
            for variant in ("orig", "flip") if use_flips else ("orig",):
                for s in strides:
                    self.entries += [("pair", vi, variant, t, s) for t in range(v.num_frames - s)]
            if use_warps:
                self.entries += [("warp", vi, w) for w in range(len(v.warp_t)) if v.warp_s[w] in strides]

    def __len__(self):
        return len(self.entries)

    def example(self, idx: int):
        """Full-grid (x [82, H, W] float32, target [34, H, W], mask [17, H, W], motions, matches)."""
        e = self.entries[idx]
        v = self.videos[e[1]]
        if e[0] == "pair":
            _, _, variant, t, s = e
            maps_a, maps_b = v.maps[variant][t], v.maps[variant][t + s]
            kps_a, kps_b = v.kps[variant][t], v.kps[variant][t + s]
            matches = self._matches(v, variant, t, s, kps_a, kps_b)
            ignore_b = v.ignore[variant][t + s] if v.ignore else None
        else:
            w = e[2]
            variant = "flip" if v.warp_flip[w] else "orig"
            t, s = int(v.warp_t[w]), int(v.warp_s[w])
            maps_a, maps_b = v.maps[variant][t], v.warp_maps[w]
            kps_a = v.kps[variant][t]
            # Correspondences are decided before the warp (it is synthetic motion, not a person's).
            matches = self._matches(v, variant, t, s, kps_a, v.kps[variant][t + s])
            kps_b = [transform_kps(k, v.warp_affine[w]) for k in v.kps[variant][t + s]]
            ignore_b = v.warp_ignore[w] if v.ignore else None
        motions, mask = motions_and_mask(kps_a, kps_b, matches, v.grid_hw,
                                         ignore_joints=UNMAPPED_JOINTS if v.tracks else ())
        if v.ignore:  # PoseTrack's unannotated regions, in either frame (paper: M = 0 there)
            mask *= (1 - v.ignore[variant][t]) * (1 - ignore_b)
        target = render_tff(motions, NUM_JOINTS, v.grid_hw, self.sigma)
        x = np.concatenate([maps_a, maps_b]).astype(np.float32)
        return x, target, mask, motions, (kps_a, kps_b, matches)

    @staticmethod
    def _matches(v: Video, variant: str, t: int, s: int, kps_a, kps_b):
        """Ground-truth identities where the source has them, else the conservative association."""
        if v.tracks is None:
            return associate(kps_a, kps_b)
        ta, tb = v.tracks[variant][t][:len(kps_a)], list(v.tracks[variant][t + s][:len(kps_b)])
        return [(i, tb.index(tid)) for i, tid in enumerate(ta) if tid >= 0 and tid in tb]

    def crop(self, idx: int, size: int, rng: np.random.Generator, near_motion: float = 0.7):
        """A size x size window (zero input and mask outside the grid), centred near a random
        labelled joint motion with probability near_motion."""
        x, target, mask, motions, _ = self.example(idx)
        h, w = x.shape[1:]
        if motions and rng.random() < near_motion:
            _, f, t = motions[int(rng.integers(len(motions)))]
            cx, cy = (f[0] + t[0]) / 2 + rng.normal(0, size / 6), (f[1] + t[1]) / 2 + rng.normal(0, size / 6)
        else:
            cx, cy = rng.uniform(0, w), rng.uniform(0, h)
        x0 = int(np.clip(round(cx - size / 2), min(0, w - size), max(0, w - size))) // 2 * 2
        y0 = int(np.clip(round(cy - size / 2), min(0, h - size), max(0, h - size))) // 2 * 2
        out = [np.zeros((a.shape[0], size, size), np.float32) for a in (x, target, mask)]
        sx0, sy0 = max(0, x0), max(0, y0)
        sx1, sy1 = min(w, x0 + size), min(h, y0 + size)
        for o, a in zip(out, (x, target, mask)):
            o[:, sy0 - y0:sy1 - y0, sx0 - x0:sx1 - x0] = a[:, sy0:sy1, sx0:sx1]
        return out
