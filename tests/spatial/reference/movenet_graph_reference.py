#!/usr/bin/env python3
"""Reference outputs of MoveNet MultiPose's own post-processing, for the C++ decoder's test.

Converts the complete TF.js graph (post-processing included, which OpenCV cannot run) with the
models' pinned tf2onnx, runs it in onnxruntime on vtest.avi frames, and writes per case
  heads_<case>.bin  the six raw heads, NCHW float32, each preceded by its 4 int32 dims
                    (center, heatmaps, regression, offsets, box_scale, box_offset);
  ref_<case>.json   the graph's 6 persons: score, box and keypoints in grid cells.
The Catch2 test "MoveNet decoding equals the original graph" reads them from
$JOINTFLOW_MOVENET_REFERENCE.

Usage (with the venv that models/convert/convert.sh makes):
  models/convert/.venv/bin/python tests/spatial/reference/movenet_graph_reference.py OUTDIR
"""
import json
import os
import subprocess
import sys

import cv2
import numpy as np
import onnxruntime as ort

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "training"))
from jointflow_train.spatial import shrink_image  # noqa: E402  (the letterbox's shrink)
TFJS = os.path.join(ROOT, "models/convert/.cache/work/movenet-multipose.json")  # patched by convert.sh
VTEST = os.environ.get("JOINTFLOW_VTEST", "/usr/share/doc/opencv-doc/examples/data/vtest.avi")
S = "StatefulPartitionedCall/"
HEADS = [S + "Sigmoid:0", S + "Sigmoid_1:0", S + "kpt_regress_0/conv2d_8/BiasAdd:0",
         S + "kpt_offset_0/conv2d_9/BiasAdd:0", S + "box_scale_0/conv2d_5/BiasAdd:0",
         S + "box_offset_0/conv2d_6/BiasAdd:0"]
# (case, frame, square letterbox side or 0 for the native 768x576)
CASES = [("f200_native", 200, 0), ("f300_256", 300, 256), ("f500_384", 500, 384)]


def frame_rgb(index, side):
    cap = cv2.VideoCapture(VTEST)
    cap.set(cv2.CAP_PROP_POS_FRAMES, index)
    ok, bgr = cap.read()
    assert ok, f"cannot read frame {index} of {VTEST}"
    rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
    if side:
        h, w = rgb.shape[:2]
        k = side / max(h, w)
        small = shrink_image(rgb, round(w * k), round(h * k))
        rgb = np.zeros((side, side, 3), np.uint8)
        rgb[: small.shape[0], : small.shape[1]] = small
    return rgb


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    full = os.path.join(out, "movenet_full.onnx")
    if not os.path.exists(full):
        subprocess.check_call([sys.executable, "-m", "tf2onnx.convert", "--tfjs", TFJS,
                               "--inputs", "input:0[1,-1,-1,3]", "--inputs-as-nchw", "input:0",
                               "--outputs", ",".join(["Identity:0"] + HEADS), "--opset", "13",
                               "--output", full], env=dict(os.environ, PYTHONHASHSEED="0"))
    sess = ort.InferenceSession(full)
    names = [o.name for o in sess.get_outputs()]
    for case, index, side in CASES:
        x = frame_rgb(index, side).transpose(2, 0, 1)[None].astype(np.int32)
        outs = dict(zip(names, sess.run(None, {sess.get_inputs()[0].name: x})))
        with open(os.path.join(out, f"heads_{case}.bin"), "wb") as f:
            for n in HEADS:
                a = outs[n].reshape(outs[n].shape[-3:])  # NHWC without batch
                a = np.ascontiguousarray(a.transpose(2, 0, 1)[None].astype(np.float32))
                f.write(np.array(a.shape, np.int32).tobytes())
                f.write(a.tobytes())
        gh, gw = x.shape[2] / 4, x.shape[3] / 4
        persons = []
        for p in outs["Identity:0"][0]:
            kp = p[:51].reshape(17, 3)
            persons.append({
                "score": float(p[55]),
                # normalised [ymin, xmin, ymax, xmax] -> cells
                "box": [float(p[51] * gh), float(p[52] * gw), float(p[53] * gh), float(p[54] * gw)],
                "keypoints": [[float(k[1] * gw), float(k[0] * gh), float(k[2])] for k in kp],
            })
        with open(os.path.join(out, f"ref_{case}.json"), "w") as f:
            json.dump({"frame": index, "input": [int(x.shape[3]), int(x.shape[2])],
                       "persons": persons}, f)
        print(case, "written")


if __name__ == "__main__":
    main()
