"""PoseTrack-format ground truth (PoseTrack 2018 JSON: images, annotations with track_id and 17
keypoints, ignore_regions_x/y) as a training source, cached like a pseudo-labelled video
(cache.py) plus track ids and ignore masks, so that correspondences come from the annotated
identities instead of the conservative association.

PoseTrack's joints follow COCO's order except 1, 2 (head_bottom, head_top instead of the eyes)
and 3, 4 (ears, never annotated): those four channels get M = 0 (no ground truth for MoveNet's
eye and ear joints); the remaining 13 are COCO's.
"""
from __future__ import annotations

import json
import os

import cv2
import numpy as np

from .cache import MAX_PERSONS, affine_to_grid, draw_warp_frame, maps_and_poses, random_affine
from .spatial import FLIP_JOINT, NUM_JOINTS, MoveNet, fit_input

UNMAPPED_JOINTS = (1, 2, 3, 4)


def load_sequence(json_path: str, image_root: str):
    """Labelled frames of one PoseTrack 2018 sequence file, in frame order: dicts with `path`,
    `persons` [(track_id, kps [17, 3] frame pixels, visibility as score)], `ignore` [polygons]."""
    with open(json_path) as f:
        doc = json.load(f)
    for key in ("images", "annotations"):
        if key not in doc:
            raise ValueError(f"{json_path}: not a PoseTrack 2018 file, no '{key}'")
    by_image = {}
    for a in doc["annotations"]:
        kp = a.get("keypoints") or []
        if len(kp) != 3 * NUM_JOINTS or "track_id" not in a:
            continue
        k = np.array(kp, np.float32).reshape(NUM_JOINTS, 3)
        k[:, 2] = (k[:, 2] > 0).astype(np.float32)
        k[list(UNMAPPED_JOINTS), 2] = 0
        by_image.setdefault(a["image_id"], []).append((int(a["track_id"]), k))
    frames = []
    for im in sorted(doc["images"], key=lambda i: i.get("frame_id", i["id"])):
        if not im.get("is_labeled", True):
            continue
        polys = [np.stack([xs, ys], 1).astype(np.float32)
                 for xs, ys in zip(im.get("ignore_regions_x", []), im.get("ignore_regions_y", [])) if len(xs) >= 3]
        frames.append(dict(path=os.path.join(image_root, im["file_name"]), persons=by_image.get(im["id"], []),
                           ignore=polys))
    return frames


def frame_to_grid(points: np.ndarray, frame_wh, content_wh, stride: int = 4) -> np.ndarray:
    """Frame pixels -> grid cells under fit_input (pixel centres: input = (x + 0.5) * factor - 0.5,
    jointflow/letterbox.hpp; cell = input / stride)."""
    f = np.array(content_wh, np.float32) / np.array(frame_wh, np.float32)
    return ((points + 0.5) * f - 0.5) / stride


def _grid_annotations(frame, img_wh, content_wh, grid_wh, flip: bool):
    w = img_wh[0]
    kps = np.zeros((MAX_PERSONS, NUM_JOINTS, 3), np.float32)
    tracks = np.full(MAX_PERSONS, -1, np.int32)
    for n, (tid, k) in enumerate(frame["persons"][:MAX_PERSONS]):
        k = k.copy()
        if flip:
            k[:, 0] = w - 1 - k[:, 0]
            k = k[FLIP_JOINT]
        k[:, :2] = frame_to_grid(k[:, :2], img_wh, content_wh)
        kps[n], tracks[n] = k, tid
    ignore = np.zeros(grid_wh[::-1], np.uint8)
    for poly in frame["ignore"]:
        p = poly.copy()
        if flip:
            p[:, 0] = w - 1 - p[:, 0]
        cv2.fillPoly(ignore, [np.round(frame_to_grid(p, img_wh, content_wh)).astype(np.int32)], 1)
    return kps, tracks, min(len(frame["persons"]), MAX_PERSONS), ignore


def build_posetrack_cache(json_path: str, image_root: str, out_file: str, net: MoveNet, max_side: int,
                          num_warps: int, rng: np.random.Generator, max_stride: int = 3, log=print):
    frames = load_sequence(json_path, image_root)
    if len(frames) < 2:
        raise ValueError(f"{json_path}: fewer than 2 labelled frames, no pairs")
    data = {"max_side": np.int32(max_side), "source": np.str_(json_path)}
    images = []
    for fr in frames:
        img = cv2.imread(fr["path"])
        if img is None:
            raise ValueError(f"{fr['path']}: missing or unreadable image")
        images.append(img)
    for variant in ("orig", "flip"):
        cols = {k: [] for k in ("maps", "kps", "count", "track", "ignore")}
        for fr, img in zip(frames, images):
            im = img if variant == "orig" else cv2.flip(img, 1)
            rgb = fit_input(im, max_side)
            maps, _, _ = maps_and_poses(net, rgb)
            factor = min(1.0, max_side / max(img.shape[:2]))
            content = (max(1, int(np.floor(img.shape[1] * factor + 0.5))), max(1, int(np.floor(img.shape[0] * factor + 0.5))))
            kps, tracks, count, ignore = _grid_annotations(fr, (img.shape[1], img.shape[0]), content,
                                                           (maps.shape[2], maps.shape[1]), variant == "flip")
            for k, v in zip(("maps", "kps", "count", "track", "ignore"), (maps, kps, count, tracks, ignore)):
                cols[k].append(v)
        for k, v in cols.items():
            data[f"{variant}_{k}"] = np.stack(v) if k != "count" else np.array(v, np.int32)
    wt, ws, wf, wa, wmaps, wign = [], [], [], [], [], []
    for _ in range(num_warps):
        s, t, flip, im = draw_warp_frame(rng, images, max_stride)
        rgb = fit_input(im, max_side)
        a = random_affine(rng, (rgb.shape[1], rgb.shape[0]))
        m, _, _ = maps_and_poses(net, cv2.warpAffine(rgb, a, (rgb.shape[1], rgb.shape[0])))
        g = affine_to_grid(a)
        ign = data[f"{'flip' if flip else 'orig'}_ignore"][t + s]
        wt.append(t), ws.append(s), wf.append(flip), wa.append(g), wmaps.append(m)
        wign.append(cv2.warpAffine(ign, g, (ign.shape[1], ign.shape[0]), flags=cv2.INTER_NEAREST))
    data.update(warp_t=np.array(wt, np.int32), warp_s=np.array(ws, np.int32), warp_flip=np.array(wf, bool),
                warp_affine=np.array(wa, np.float32).reshape(-1, 2, 3),
                warp_maps=np.stack(wmaps) if wmaps else np.zeros((0,) + data["orig_maps"].shape[1:], np.float16),
                warp_ignore=np.stack(wign) if wign else np.zeros((0,) + data["orig_ignore"].shape[1:], np.uint8))
    np.savez(out_file, **data)
    log(f"{os.path.basename(json_path)}: {len(frames)} labelled frames at max:{max_side}, "
        f"{sum(len(f['persons']) for f in frames)} person annotations, {num_warps} warps")
