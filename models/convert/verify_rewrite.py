#!/usr/bin/env python3
"""Check the rewritten ONNX graphs against tf2onnx's graphs (onnxruntime, both), and check the
channel conventions documented in models/README.md on a real frame.

Usage: verify_rewrite.py WORK_DIR MODELS_DIR
  WORK_DIR holds movenet_raw.onnx / posenet_raw.onnx (tf2onnx output, NHWC outputs,
  MoveNet input int32); MODELS_DIR holds the final files.
"""
import os
import sys

import cv2
import numpy as np
import onnxruntime as ort

VTEST = "/usr/share/doc/opencv-doc/examples/data/vtest.avi"
MESSI = "/usr/share/doc/opencv-doc/examples/data/messi5.jpg"

# graph rewrite must be exact up to float rounding (Resize vs ConvTranspose summation order)
REWRITE_TOL = 1e-3


def frame(index=200):
    cap = cv2.VideoCapture(VTEST)
    cap.set(cv2.CAP_PROP_POS_FRAMES, index)
    ok, img = cap.read()
    if not ok:
        img = cv2.imread(MESSI)
    return img


def to_nchw(img_bgr, h, w):
    """Top-left aligned, zero padded RGB float NCHW blob of size h x w (no resize if it fits)."""
    ih, iw = img_bgr.shape[:2]
    if ih > h or iw > w:
        s = min(h / ih, w / iw)
        img_bgr = cv2.resize(img_bgr, (int(iw * s), int(ih * s)), interpolation=cv2.INTER_AREA)
        ih, iw = img_bgr.shape[:2]
    x = np.zeros((1, 3, h, w), np.float32)
    x[0, :, :ih, :iw] = img_bgr[:, :, ::-1].transpose(2, 0, 1)
    return x


def session(path):
    return ort.InferenceSession(path, providers=["CPUExecutionProvider"])


def compare(raw, final, feeds_raw, feeds_final, label):
    r_out = raw.run(None, feeds_raw)
    f_out = final.run(None, feeds_final)
    names = [o.name for o in final.get_outputs()]
    worst = 0.0
    for name, r, f in zip(names, r_out, f_out):
        r = r.reshape(f.shape[0], f.shape[2], f.shape[3], f.shape[1]).transpose(0, 3, 1, 2)
        d = float(np.abs(r - f).max())
        worst = max(worst, d)
        assert d < REWRITE_TOL, f"{label} {name}: rewrite differs by {d}"
    print(f"  {label}: rewritten == tf2onnx graph, max abs diff {worst:.2e}")
    return dict(zip(names, f_out))


def check_movenet_conventions(out):
    """2j = dy, 2j+1 = dx: regressed joints must land on heatmap peaks, and head above ankles."""
    c = out["center"][0, 0]
    peaks = np.argwhere((c == cv2.dilate(c, np.ones((5, 5), np.uint8))) & (c > 0.4))
    assert len(peaks) >= 3, f"MoveNet found only {len(peaks)} people in vtest frame 200"
    hm, reg = out["heatmaps"][0], out["regression"][0]
    yy, xx = np.mgrid[: c.shape[0], : c.shape[1]]
    d_norm, d_swap = [], []
    for i, j in peaks:
        r = reg[:, i, j].reshape(17, 2)
        assert r[0, 0] < 0 < r[15, 0] and r[0, 0] < 0 < r[16, 0], "nose must be above ankles"
        for k in range(17):
            for swap, acc in ((False, d_norm), (True, d_swap)):
                dy, dx = (r[k, 1], r[k, 0]) if swap else (r[k, 0], r[k, 1])
                d = np.hypot(yy - (i + dy), xx - (j + dx))
                a = np.unravel_index(np.argmax(hm[k] / (d + 1.8) * (d < 10)), d.shape)
                acc.append(np.hypot(a[0] - (i + dy), a[1] - (j + dx)))
    print(f"  MoveNet: {len(peaks)} centres > 0.4; regressed joint to heatmap peak "
          f"{np.mean(d_norm):.2f} cells as (dy,dx), {np.mean(d_swap):.2f} if swapped")
    assert np.mean(d_norm) < 1.5 and np.mean(d_swap) > 2 * np.mean(d_norm)


def check_posenet_conventions(out):
    """0-15 = dy, 16-31 = dx: forward edge 8 (left hip -> left knee) points down."""
    hip = out["heatmaps"][0, 11]
    peaks = np.argwhere((hip == cv2.dilate(hip, np.ones((3, 3), np.uint8))) & (hip > 2.0))
    assert len(peaks) >= 3, f"PoseNet found only {len(peaks)} left hips"
    fwd = out["displacement_fwd"][0]
    dy = np.array([fwd[8, i, j] for i, j in peaks])
    dx = np.array([fwd[24, i, j] for i, j in peaks])
    print(f"  PoseNet: {len(peaks)} left hips; hip->knee displacement mean dy {dy.mean():.1f} px, "
          f"mean |dx| {np.abs(dx).mean():.1f} px")
    assert dy.mean() > 5 and dy.mean() > 2 * np.abs(dx).mean()


def main():
    work, models = sys.argv[1], sys.argv[2]
    img = frame()
    print("verify_rewrite:")
    raw = session(os.path.join(work, "movenet_raw.onnx"))
    final = session(os.path.join(models, "movenet_multipose.onnx"))
    for h, w in ((256, 256), (576, 768)):
        x = to_nchw(img, h, w).round()
        out = compare(raw, final, {raw.get_inputs()[0].name: x.astype(np.int32)},
                      {"input": x}, f"movenet {h}x{w}")
    check_movenet_conventions(out)
    raw = session(os.path.join(work, "posenet_raw.onnx"))
    final = session(os.path.join(models, "posenet_mobilenetv1.onnx"))
    for h, w in ((257, 257), (577, 769)):
        x = to_nchw(img, h, w) / 127.5 - 1.0
        out = compare(raw, final, {raw.get_inputs()[0].name: x}, {"image": x},
                      f"posenet {h}x{w}")
    check_posenet_conventions(out)


if __name__ == "__main__":
    main()
