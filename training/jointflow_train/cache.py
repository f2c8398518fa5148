"""Precomputes, once per video, what training needs from the spatial model: features + belief maps
(float16) and decoded poses of every frame, for the frame as it is and mirrored, plus a number of
frames warped by a random affine map (synthetic camera motion). Training then never runs MoveNet.

Flips and warps are applied to the image *before* MoveNet, so the network is trained on the maps
MoveNet really produces for such frames. MoveNet labels left and right by anatomy, so poses
decoded from a mirrored frame already carry swapped joint indices; poses carried through a warp
keep theirs.
"""
from __future__ import annotations

import glob
import os
from typing import List

import cv2
import numpy as np

from .spatial import FEATURE_CHANNELS, NUM_JOINTS, MoveNet, decode, fit_input

MAX_PERSONS = 10


def read_frames(path: str, max_frames: int, start: int = 0) -> List[np.ndarray]:
    """BGR frames [start, start + max_frames) of a video file (anything OpenCV decodes, GIF too) or
    of a folder of images (sorted by name)."""
    if os.path.isdir(path):
        files = sorted(glob.glob(os.path.join(path, "*.jpg")) + glob.glob(os.path.join(path, "*.png")))
        frames = [cv2.imread(f) for f in files[start:start + max_frames]]
    else:
        cap = cv2.VideoCapture(path)
        if not cap.isOpened():
            raise ValueError(f"{path}: cannot open as a video")
        cap.set(cv2.CAP_PROP_POS_FRAMES, start)
        frames = []
        while len(frames) < max_frames:
            ok, frame = cap.read()
            if not ok:
                break
            frames.append(frame)
    frames = [f for f in frames if f is not None and f.size]
    if len(frames) < 4:
        raise ValueError(f"{path}: fewer than 4 readable frames")
    return frames


def maps_and_poses(net: MoveNet, rgb: np.ndarray):
    out = net(rgb)
    maps = np.concatenate([out["features"], out["heatmaps"]]).astype(np.float16)
    kps = np.zeros((MAX_PERSONS, NUM_JOINTS, 3), np.float32)
    poses = decode(out, max_persons=MAX_PERSONS)
    for i, p in enumerate(poses):
        kps[i] = p.kps
    return maps, kps, len(poses)


def choose_max_side(net: MoveNet, frames, candidates=(384, 512)) -> int:
    """The run-time "max:N" size at which MoveNet sees the people of this video: the smallest
    candidate that finds at least 80 % of the most confident persons any candidate finds."""
    idx = np.linspace(0, len(frames) - 1, 3).round().astype(int)
    found = []
    for side in candidates:
        n = 0
        for i in idx:
            _, kps, count = maps_and_poses(net, fit_input(frames[i], side))
            n += count
        found.append(n)
    best = max(found)
    for side, n in zip(candidates, found):
        if n >= 0.8 * best:
            return side
    return candidates[-1]


def random_affine(rng: np.random.Generator, size_wh, max_rot_deg=5.0, max_scale=0.08, max_shift=0.06):
    """A camera-motion-like affine map of input pixels (rotation about the centre, zoom, pan)."""
    w, h = size_wh
    a = cv2.getRotationMatrix2D((w / 2, h / 2), float(rng.uniform(-max_rot_deg, max_rot_deg)),
                                float(1 + rng.uniform(-max_scale, max_scale)))
    a[:, 2] += rng.uniform(-max_shift, max_shift, 2) * (w, h)
    return a.astype(np.float32)


def affine_to_grid(a_input: np.ndarray, stride: int = 4) -> np.ndarray:
    """The same map on grid cells (cell = input pixel / stride): same linear part, shift / stride."""
    g = a_input.copy()
    g[:, 2] /= stride
    return g


def build_video_cache(path: str, out_file: str, net: MoveNet, max_frames: int, num_warps: int,
                      rng: np.random.Generator, max_side: int = 0, max_stride: int = 3, log=print):
    frames = read_frames(path, max_frames)
    side = max_side or choose_max_side(net, frames)
    data = {"max_side": np.int32(side), "source": np.str_(path)}
    for variant in ("orig", "flip"):
        maps, kps, counts = [], [], []
        for f in frames:
            m, k, c = maps_and_poses(net, fit_input(f if variant == "orig" else cv2.flip(f, 1), side))
            maps.append(m)
            kps.append(k)
            counts.append(c)
        data[f"{variant}_maps"] = np.stack(maps)
        data[f"{variant}_kps"] = np.stack(kps)
        data[f"{variant}_count"] = np.array(counts, np.int32)
    # Synthetic camera motion: frame t+s (mirrored or not) warped, its maps recomputed.
    wt, ws, wf, wa, wmaps = [], [], [], [], []
    for _ in range(num_warps):
        s = int(rng.integers(1, max_stride + 1))
        t = int(rng.integers(0, len(frames) - s))
        flip = bool(rng.integers(0, 2))
        f = frames[t + s] if not flip else cv2.flip(frames[t + s], 1)
        rgb = fit_input(f, side)
        a = random_affine(rng, (rgb.shape[1], rgb.shape[0]))
        warped = cv2.warpAffine(rgb, a, (rgb.shape[1], rgb.shape[0]), flags=cv2.INTER_LINEAR,
                                borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        m, _, _ = maps_and_poses(net, warped)
        wt.append(t), ws.append(s), wf.append(flip), wa.append(affine_to_grid(a)), wmaps.append(m)
    data.update(warp_t=np.array(wt, np.int32), warp_s=np.array(ws, np.int32),
                warp_flip=np.array(wf, bool), warp_affine=np.array(wa, np.float32).reshape(-1, 2, 3),
                warp_maps=np.stack(wmaps) if wmaps else np.zeros((0, FEATURE_CHANNELS + NUM_JOINTS, 1, 1), np.float16))
    np.savez(out_file, **data)
    log(f"{os.path.basename(path)}: {len(frames)} frames at max:{side} -> grid "
        f"{data['orig_maps'].shape[3]}x{data['orig_maps'].shape[2]}, mean persons "
        f"{data['orig_count'].mean():.1f}, {num_warps} warps")
