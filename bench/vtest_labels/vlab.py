"""Shared helpers of the vtest.avi labelling tools: MOT files, frames, drawing.

Frames are read from FRAMES_DIR (PNG per frame, numbered from 1, decoded once from vtest.avi by
`decode.py`; never committed) so that the tools can seek cheaply."""
import os
import cv2
import numpy as np

VIDEO = "/usr/share/doc/opencv-doc/examples/data/vtest.avi"
FRAMES_DIR = os.environ.get("VTEST_FRAMES", "/tmp/label/frames")
W, H, N = 768, 576, 795


def frame(f):
    return cv2.imread(os.path.join(FRAMES_DIR, "%04d.png" % f))


def read_mot(path):
    """{frame: {id: (x, y, w, h)}} of a MOT file."""
    out = {}
    for line in open(path):
        v = line.strip().split(",")
        if len(v) < 6:
            continue
        f, i = int(float(v[0])), int(float(v[1]))
        out.setdefault(f, {})[i] = tuple(float(x) for x in v[2:6])
    return out


def write_mot(path, boxes, gt=True):
    with open(path, "w") as out:
        for f in sorted(boxes):
            for i in sorted(boxes[f]):
                x, y, w, h = boxes[f][i]
                tail = "1,1,1.0" if gt else "1,-1,-1,-1"
                out.write("%d,%d,%.1f,%.1f,%.1f,%.1f,%s\n" % (f, i, x, y, w, h, tail))


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
