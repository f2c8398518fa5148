"""Shared helpers of the vtest.avi labelling tools: MOT files, frames, drawing.

Frames are read from FRAMES_DIR (PNG per frame, numbered from 1, decoded once from vtest.avi by
`decode.py`; never committed) so that the tools can seek cheaply."""
import argparse
import os
import cv2
import numpy as np
from motfile import by_id, read_mot  # noqa: F401 (the tools import them from here)

VIDEO = "/usr/share/doc/opencv-doc/examples/data/vtest.avi"
FRAMES_DIR = os.environ.get("VTEST_FRAMES", "/tmp/label/frames")
W, H, N = 768, 576, 795


def arguments(*names):
    """An argument parser with the tools' common arguments (boxes, out, ids) among NAMES."""
    a = argparse.ArgumentParser()
    for name in names:
        if name == "ids":
            a.add_argument("--ids", default="", help="comma-separated ids (default: all)")
        else:
            a.add_argument(name)
    return a


def frame(f):
    return cv2.imread(os.path.join(FRAMES_DIR, "%04d.png" % f))


def colour(i):
    rng = np.random.RandomState(i * 7919 % 100003)
    return tuple(int(c) for c in rng.randint(60, 256, 3))


def draw(img, boxes, scale=1.0, thick=2, font=0.9):
    for i, (x, y, w, h) in sorted(boxes.items()):
        c = colour(i)
        p0 = (int(x * scale), int(y * scale))
        p1 = (int((x + w) * scale), int((y + h) * scale))
        cv2.rectangle(img, p0, p1, c, thick)
        org = (p0[0], max(p0[1] - 3, 14))
        cv2.putText(img, str(i), org, 0, font, (0, 0, 0), 4)
        cv2.putText(img, str(i), org, 0, font, c, 2)
    return img


def grid(tiles, cols):
    h, w = tiles[0].shape[:2]
    rows = (len(tiles) + cols - 1) // cols
    out = np.zeros((rows * h, cols * w, 3), np.uint8)
    for k, t in enumerate(tiles):
        r, c = divmod(k, cols)
        out[r * h:(r + 1) * h, c * w:(c + 1) * w] = t
    return out
