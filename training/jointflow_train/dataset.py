"""Training pairs from the cached maps (cache.py): input maps of frames t and t+s, the rendered
TFF target (paper Eq. 2-4) and the loss mask M (Eq. 5).

Augmentations (issues 6 and 12): frame strides s (default 1-4), mirrored frames (MoveNet run on
the mirrored image; its poses come with left/right already swapped), synthetic camera motion
(frame t+s warped by a random affine map before MoveNet, its poses carried through the same map:
pans up to ~120 frame pixels, zoom, rotation), time-reversed pairs (frame t+s first: every pair
also exists backwards, so the field must not assume that people move forward), and random crops
of the grid (the network is fully convolutional).

Identities of pseudo-labelled videos: the conservative association (pseudo_labels.associate) of
consecutive frames, chained into tracks; a pair (t, t+s) matches the people whose chains run from t
to t+s. Chaining carries identities through moments where two people are close, at which a direct
association of frames s apart would be ambiguous and leave them out: those pairs are the "crossing"
pairs (two matched people whose keypoint boxes overlap in either frame), sampled with their own
share of each batch.
"""
from __future__ import annotations

import os
from typing import List, Sequence

import numpy as np

from .cache import maps_paths
from .posetrack import UNMAPPED_JOINTS
from .pseudo_labels import associate, keypoint_box, motions_and_mask
from .tff_render import render_tff

NUM_JOINTS = 17
CROSSING_IOU = 0.1


def box_iou(a, b) -> float:
    ix = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    iy = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    inter = ix * iy
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def chain_tracks(kps: Sequence[np.ndarray]) -> List[np.ndarray]:
    """Track ids per frame (one per person, -1 never happens: every person starts or continues a
    track) from the conservative association of consecutive frames."""
    ids, next_id = [], 0
    for t, k in enumerate(kps):
        cur = np.full(len(k), -1, np.int64)
        if t > 0:
            for i, j in associate(kps[t - 1], k):
                cur[j] = ids[t - 1][i]
        for j in range(len(k)):
            if cur[j] < 0:
                cur[j] = next_id
                next_id += 1
        ids.append(cur)
    return ids


class Video:
    def __init__(self, path: str):
        d = np.load(path)
        self.name = str(d["source"])
        self.stem = os.path.basename(path)[:-len(".npz")]
        if "orig_maps" in d.files:  # PoseTrack caches (and caches of issue 6) hold the maps inline
            self.maps = {v: d[f"{v}_maps"] for v in ("orig", "flip")}
            self.warp_maps = d["warp_maps"]
        else:
            maps_file, warp_file = maps_paths(path)
            m = np.load(maps_file, mmap_mode="r")
            self.maps = {"orig": m[0], "flip": m[1]}
            self.warp_maps = np.load(warp_file, mmap_mode="r")
        self.kps = {v: [d[f"{v}_kps"][i, :d[f"{v}_count"][i]] for i in range(len(d[f"{v}_count"]))]
                    for v in ("orig", "flip")}
        self.warp_t, self.warp_s, self.warp_flip = d["warp_t"], d["warp_s"], d["warp_flip"]
        self.warp_affine = d["warp_affine"]
        # Frame pixels per grid cell (the run-time unit of tau_delta is the frame pixel).
        self.max_side = int(d["max_side"])
        self.frame_wh = tuple(int(v) for v in d["frame_wh"]) if "frame_wh" in d.files else None
        self.factor = float(d["factor"]) if "factor" in d.files else None
        # PoseTrack ground truth (posetrack.py): track ids, ignore regions; pseudo-labels have none.
        self.tracks = {v: d[f"{v}_track"] for v in ("orig", "flip")} if "orig_track" in d.files else None
        self.ignore = {v: d[f"{v}_ignore"] for v in ("orig", "flip")} if "orig_ignore" in d.files else None
        self.warp_ignore = d["warp_ignore"] if "warp_ignore" in d.files else None
        self.num_frames = len(self.kps["orig"])
        self.grid_hw = tuple(self.maps["orig"].shape[2:])
        self.chains = None if self.tracks else {v: chain_tracks(self.kps[v]) for v in ("orig", "flip")}

    def pixels_per_cell(self) -> float:
        """Frame pixels per grid cell (stride 4 of the network input, input = frame x factor)."""
        return 4.0 / self.factor if self.factor else 4.0


def transform_kps(kps: np.ndarray, affine: np.ndarray) -> np.ndarray:
    out = kps.copy()
    out[..., :2] = kps[..., :2] @ affine[:, :2].T + affine[:, 2]
    return out


class PairDataset:
    """entries: ("pair", video, variant, t, s) and ("warp", video, warp index); every entry can be
    read forwards or time-reversed (example(..., reverse=True)). `crossing` lists the pair entries
    with two matched people whose boxes overlap."""

    def __init__(self, files: Sequence[str], strides=(1, 2, 3, 4), use_flips=True, use_warps=True,
                 sigma: float = 1.0):
        self.videos: List[Video] = [Video(f) for f in files]
        self.sigma = sigma
        self.entries = []
        self.crossing = []
        for vi, v in enumerate(self.videos):
            for variant in ("orig", "flip") if use_flips else ("orig",):
                for s in strides:
                    for t in range(v.num_frames - s):
                        if self._is_crossing(v, variant, t, s):
                            self.crossing.append(len(self.entries))
                        self.entries.append(("pair", vi, variant, t, s))
            if use_warps:
                self.entries += [("warp", vi, w) for w in range(len(v.warp_t)) if v.warp_s[w] in strides]

    def __len__(self):
        return len(self.entries)

    def _is_crossing(self, v: Video, variant: str, t: int, s: int) -> bool:
        matches = self._matches(v, variant, t, s, v.kps[variant][t], v.kps[variant][t + s])
        if len(matches) < 2:
            return False
        for frame, side in ((t, 0), (t + s, 1)):
            boxes = [keypoint_box(v.kps[variant][frame][m[side]]) for m in matches]
            for i in range(len(boxes)):
                for j in range(i + 1, len(boxes)):
                    if box_iou(boxes[i], boxes[j]) >= CROSSING_IOU:
                        return True
        return False

    def example(self, idx: int, reverse: bool = False):
        """Full-grid (x [82, H, W] float32, target [34, H, W], mask [17, H, W], motions, matches);
        reverse: frame t+s first, frame t second (the same pair played backwards)."""
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
        ignore_a = v.ignore[variant][t] if v.ignore else None
        if reverse:
            maps_a, maps_b, kps_a, kps_b = maps_b, maps_a, kps_b, kps_a
            matches = [(k, i) for i, k in matches]
            ignore_a, ignore_b = ignore_b, ignore_a
        motions, mask = motions_and_mask(kps_a, kps_b, matches, v.grid_hw,
                                         ignore_joints=UNMAPPED_JOINTS if v.tracks else ())
        if v.ignore:  # PoseTrack's unannotated regions, in either frame (paper: M = 0 there)
            mask *= (1 - ignore_a) * (1 - ignore_b)
        target = render_tff(motions, NUM_JOINTS, v.grid_hw, self.sigma)
        x = np.concatenate([maps_a, maps_b]).astype(np.float32)
        return x, target, mask, motions, (kps_a, kps_b, matches)

    @staticmethod
    def _matches(v: Video, variant: str, t: int, s: int, kps_a, kps_b):
        """Ground-truth identities where the source has them, else the chained conservative
        association (see the module docstring)."""
        if v.tracks is not None:
            ta, tb = v.tracks[variant][t][:len(kps_a)], list(v.tracks[variant][t + s][:len(kps_b)])
            return [(i, tb.index(tid)) for i, tid in enumerate(ta) if tid >= 0 and tid in tb]
        # s = 1: the chain links are associate(kps_a, kps_b) itself.
        ca, cb = v.chains[variant][t], list(v.chains[variant][t + s])
        return [(i, cb.index(c)) for i, c in enumerate(ca) if c in cb]

    def crop(self, idx: int, size: int, rng: np.random.Generator, near_motion: float = 0.7,
             reverse: bool = False):
        """A size x size window (zero input and mask outside the grid), centred near a random
        labelled joint motion with probability near_motion."""
        x, target, mask, motions, _ = self.example(idx, reverse)
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
