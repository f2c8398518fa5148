"""The spatial model at training time: MoveNet MultiPose ONNX (models/movenet_multipose.onnx) run by
onnxruntime (or OpenCV dnn), its features + joint belief maps, and its poses decoded in Python.

The maps are those the C++ runtime feeds the TFF network (SpatialResult::features, ::beliefs):
same ONNX file, same input normalisation (RGB float 0..255; the graph normalises). The decoding
re-implements MoveNet's own post-processing as described in shared/notes/models.md; here it only
produces pseudo-labels, so a re-implementation in Python (not a call into the C++ decoder, which
would mean one process per frame) is enough.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List

import cv2
import numpy as np

NUM_JOINTS = 17
FEATURE_CHANNELS = 24
STRIDE = 4
# COCO-17 left/right swap, for horizontal flips (same as jointflow::kFlipJoint).
FLIP_JOINT = [0, 2, 1, 4, 3, 6, 5, 8, 7, 10, 9, 12, 11, 14, 13, 16, 15]


def shrink_image(image: np.ndarray, width: int, height: int) -> np.ndarray:
    """jointflow::shrinkImage (core/include/jointflow/image_shrink.hpp): halved by INTER_AREA while
    the target is at most half of it on both sides, then INTER_LINEAR to the exact size (fast, and
    no aliasing: the bilinear step shrinks by less than 2x). The image itself when already that size."""
    while image.shape[1] >= 2 * width and image.shape[0] >= 2 * height:
        image = cv2.resize(image, (image.shape[1] // 2, image.shape[0] // 2), interpolation=cv2.INTER_AREA)
    if image.shape[:2] == (height, width):
        return image
    return cv2.resize(image, (width, height), interpolation=cv2.INTER_LINEAR)


def fit_input(frame_bgr: np.ndarray, max_side: int) -> np.ndarray:
    """The run-time input policy "max:N" (core/include/jointflow/letterbox.hpp, kMaxSide): resize
    factor min(1, max_side / longer side) by shrink_image, zero padding at the right and bottom to multiples of 32. Returns the RGB uint8 input; grid
    cell (col, row) is input pixel (4 col, 4 row)."""
    if frame_bgr is None or frame_bgr.size == 0 or frame_bgr.ndim != 3 or frame_bgr.shape[2] != 3:
        raise ValueError("fit_input: expected a non-empty 8-bit 3-channel BGR frame")
    h, w = frame_bgr.shape[:2]
    factor = min(1.0, max_side / max(h, w))
    nw, nh = max(1, int(np.floor(w * factor + 0.5))), max(1, int(np.floor(h * factor + 0.5)))
    resized = shrink_image(frame_bgr, nw, nh)
    out = np.zeros((-(-nh // 32) * 32, -(-nw // 32) * 32, 3), np.uint8)
    out[:nh, :nw] = resized
    return cv2.cvtColor(out, cv2.COLOR_BGR2RGB)


class MoveNet:
    """Runs the MoveNet ONNX file on an RGB uint8 image whose sides are multiples of 32."""

    OUTPUTS = ["center", "heatmaps", "regression", "offsets", "box_scale", "box_offset", "features"]

    def __init__(self, path: str, backend: str = "ort", threads: int = 1):
        self.backend = backend
        if backend == "ort":
            import onnxruntime as ort
            opts = ort.SessionOptions()
            opts.intra_op_num_threads = threads
            opts.inter_op_num_threads = 1
            self.sess = ort.InferenceSession(path, opts, providers=["CPUExecutionProvider"])
            names = [o.name for o in self.sess.get_outputs()]
            missing = [n for n in self.OUTPUTS if n not in names]
            if missing:
                raise ValueError(f"{path}: not a MoveNet model, outputs {missing} missing (has {names})")
        elif backend == "cv2":
            cv2.setNumThreads(threads)
            self.net = cv2.dnn.readNetFromONNX(path)
        else:
            raise ValueError(f"unknown backend {backend!r}: 'ort' or 'cv2'")

    def __call__(self, rgb: np.ndarray) -> Dict[str, np.ndarray]:
        h, w = rgb.shape[:2]
        if h % 32 or w % 32:
            raise ValueError(f"MoveNet input {w}x{h}: sides must be multiples of 32")
        blob = rgb.astype(np.float32).transpose(2, 0, 1)[None]
        if self.backend == "ort":
            outs = self.sess.run(self.OUTPUTS, {"input": blob})
        else:
            self.net.setInput(blob)
            outs = self.net.forward(self.OUTPUTS)
        return {k: v[0] for k, v in zip(self.OUTPUTS, outs)}


@dataclass
class Pose:
    kps: np.ndarray  # [17, 3]: x (column), y (row) in grid cells, score
    score: float
    box: np.ndarray  # x0, y0, x1, y1 in grid cells


def decode(maps: Dict[str, np.ndarray], max_persons: int = 10, person_threshold: float = 0.2,
           joint_threshold: float = 0.127) -> List[Pose]:
    """MoveNet MultiPose decoding (shared/notes/models.md), poses in grid cells."""
    center = maps["center"][0]
    hm, reg, off = maps["heatmaps"], maps["regression"], maps["offsets"]
    h, w = center.shape
    peaks = (center == cv2.dilate(center, np.ones((5, 5), np.uint8))) & (center > 0.05)
    ys, xs = np.nonzero(peaks)
    order = np.argsort(-center[ys, xs])[:max_persons]
    rows = np.arange(h, dtype=np.float32)[:, None]
    cols = np.arange(w, dtype=np.float32)[None, :]
    poses = []
    for cy, cx in zip(ys[order], xs[order]):
        bh, bw = maps["box_scale"][:, cy, cx]
        by, bx = cy + maps["box_offset"][0, cy, cx], cx + maps["box_offset"][1, cy, cx]
        y0, y1 = max(0, int(np.floor(by - bh / 2))), min(h - 1, int(np.ceil(by + bh / 2)))
        x0, x1 = max(0, int(np.floor(bx - bw / 2))), min(w - 1, int(np.ceil(bx + bw / 2)))
        inside = np.zeros((h, w), bool)
        inside[y0:y1 + 1, x0:x1 + 1] = True
        kps = np.zeros((NUM_JOINTS, 3), np.float32)
        spread = 0.3 * max(min(bh, bw), 1e-3)
        for j in range(NUM_JOINTS):
            ry, rx = cy + reg[2 * j, cy, cx], cx + reg[2 * j + 1, cy, cx]
            weighted = hm[j] * np.exp(-((rows - ry) ** 2 + (cols - rx) ** 2) / spread)
            weighted = np.where(inside, weighted, -1)
            iy, ix = np.unravel_index(int(np.argmax(weighted)), weighted.shape)
            kps[j] = (ix + off[2 * j + 1, iy, ix], iy + off[2 * j, iy, ix], hm[j, iy, ix])
        good = kps[:, 2] > joint_threshold
        score = float(center[cy, cx] * (kps[good, 2].mean() if good.any() else 0.0))
        if score >= person_threshold:
            poses.append(Pose(kps, score, np.array([x0, y0, x1, y1], np.float32)))
    poses.sort(key=lambda p: -p.score)
    return poses
