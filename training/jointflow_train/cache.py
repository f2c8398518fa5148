"""Precomputes, once per video, what training needs from the spatial model: features + belief maps
(float16) and decoded poses of every frame, for the frame as it is and mirrored, plus a number of
frames warped by a random affine map (synthetic camera motion: pan up to ~120 frame pixels, zoom,
a little rotation). Training then never runs MoveNet.

Layout: STEM.npz holds the poses, the warps' parameters and the sizes; the maps, which at the
run-time policy max:640 take ~1.3 MB a frame, lie beside it as STEM.maps.npy ([2, T, 41, H, W]:
plain, mirrored) and STEM.warp_maps.npy ([W, 41, H, W]) so that training memory-maps them instead
of holding ~10 GB in memory. (PoseTrack caches, posetrack.py, keep their maps inside the .npz.)

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


def draw_warp_frame(rng, frames, max_stride):
    """A camera-motion pair's frames: the stride s, the first frame t and whether it is mirrored,
    with frame t + s (mirrored so) to warp. One function for both caches, so that the videos' and
    PoseTrack's pairs are drawn alike and the random stream of a seed stays the same."""
    s = int(rng.integers(1, min(max_stride, len(frames) - 1) + 1))
    t = int(rng.integers(0, len(frames) - s))
    flip = bool(rng.integers(0, 2))
    return s, t, flip, frames[t + s] if not flip else cv2.flip(frames[t + s], 1)


def random_affine(rng: np.random.Generator, size_wh, max_rot_deg=5.0, max_scale=0.08, max_shift=0.06,
                  max_shift_px: float = 0.0):
    """A camera-motion-like affine map of input pixels (rotation about the centre, zoom, pan).
    The pan is uniform in +-max_shift of the image size per axis, or, with max_shift_px > 0,
    uniform in a disc of that radius (input pixels)."""
    w, h = size_wh
    a = cv2.getRotationMatrix2D((w / 2, h / 2), float(rng.uniform(-max_rot_deg, max_rot_deg)),
                                float(1 + rng.uniform(-max_scale, max_scale)))
    if max_shift_px > 0:
        r, phi = max_shift_px * np.sqrt(rng.uniform()), rng.uniform(0, 2 * np.pi)
        a[:, 2] += (r * np.cos(phi), r * np.sin(phi))
    else:
        a[:, 2] += rng.uniform(-max_shift, max_shift, 2) * (w, h)
    return a.astype(np.float32)


def affine_to_grid(a_input: np.ndarray, stride: int = 4) -> np.ndarray:
    """The same map on grid cells (cell = input pixel / stride): same linear part, shift / stride."""
    g = a_input.copy()
    g[:, 2] /= stride
    return g


# Synthetic camera motion of the training warps (issue 12): pans up to this many *frame* pixels
# (the identity benchmark shakes the 960x540 Bonn frames by ~100 px), zoom and rotation.
MAX_PAN_FRAME_PX = 120.0
MAX_ZOOM = 0.15
MAX_ROTATION_DEG = 3.0


def maps_paths(out_file: str):
    """The side files of a video cache STEM.npz: (STEM.maps.npy, STEM.warp_maps.npy)."""
    stem = out_file[:-len(".npz")] if out_file.endswith(".npz") else out_file
    return stem + ".maps.npy", stem + ".warp_maps.npy"


def build_video_cache(path: str, out_file: str, net: MoveNet, max_frames: int, num_warps: int,
                      rng: np.random.Generator, max_side: int = 0, max_stride: int = 4, log=print,
                      final_file: str = ""):
    """Caches one video. The side files are named after final_file (default out_file), so that a
    caller can write out_file under a temporary name and rename it last: the .npz appears only
    when everything is there."""
    frames = read_frames(path, max_frames)
    side = max_side or choose_max_side(net, frames)
    fh, fw = frames[0].shape[:2]
    factor = min(1.0, side / max(fh, fw))
    data = {"max_side": np.int32(side), "source": np.str_(path), "frame_wh": np.array([fw, fh], np.int32),
            "factor": np.float32(factor)}
    maps_file, warp_file = maps_paths(final_file or out_file)
    all_maps = None
    for vi, variant in enumerate(("orig", "flip")):
        kps, counts = [], []
        for fi, f in enumerate(frames):
            m, k, c = maps_and_poses(net, fit_input(f if variant == "orig" else cv2.flip(f, 1), side))
            if all_maps is None:
                all_maps = np.lib.format.open_memmap(maps_file + ".tmp.npy", "w+", np.float16,
                                                     (2, len(frames)) + m.shape)
            all_maps[vi, fi] = m
            kps.append(k)
            counts.append(c)
        data[f"{variant}_kps"] = np.stack(kps)
        data[f"{variant}_count"] = np.array(counts, np.int32)
    all_maps.flush()
    grid_shape = all_maps.shape[2:]
    del all_maps
    # Synthetic camera motion: frame t+s (mirrored or not) warped, its maps recomputed.
    wt, ws, wf, wa = [], [], [], []
    warp_maps = np.lib.format.open_memmap(warp_file + ".tmp.npy", "w+", np.float16, (num_warps,) + grid_shape)
    for n in range(num_warps):
        s, t, flip, f = draw_warp_frame(rng, frames, max_stride)
        rgb = fit_input(f, side)
        a = random_affine(rng, (rgb.shape[1], rgb.shape[0]), MAX_ROTATION_DEG, MAX_ZOOM,
                          max_shift_px=MAX_PAN_FRAME_PX * factor)
        warped = cv2.warpAffine(rgb, a, (rgb.shape[1], rgb.shape[0]), flags=cv2.INTER_LINEAR,
                                borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        m, _, _ = maps_and_poses(net, warped)
        warp_maps[n] = m
        wt.append(t), ws.append(s), wf.append(flip), wa.append(affine_to_grid(a))
    warp_maps.flush()
    del warp_maps
    data.update(warp_t=np.array(wt, np.int32), warp_s=np.array(ws, np.int32),
                warp_flip=np.array(wf, bool), warp_affine=np.array(wa, np.float32).reshape(-1, 2, 3))
    os.replace(maps_file + ".tmp.npy", maps_file)
    os.replace(warp_file + ".tmp.npy", warp_file)
    np.savez(out_file, **data)
    log(f"{os.path.basename(path)}: {len(frames)} frames {fw}x{fh} at max:{side} -> grid "
        f"{grid_shape[2]}x{grid_shape[1]}, mean persons {data['orig_count'].mean():.1f}, {num_warps} warps")
