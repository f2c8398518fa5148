#!/usr/bin/env python3
"""Training-time vs run-time TFF inputs: the features and belief maps training caches come from
onnxruntime; the C++ runtime computes them with OpenCV 4.6 dnn on the same ONNX file and the same
input policy ("max:N", jointflow/letterbox.hpp). This runs both engines on the same input tensors
(OpenCV through its Python binding, opencv-python-headless 4.6.0.66, the version the C++ build
uses) and prints the largest differences.

Usage: training/.venv/bin/python training/check_inputs.py [--frames 4] [VIDEO ...]
"""
import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.cache import read_frames  # noqa: E402
from jointflow_train.spatial import MoveNet, fit_input  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("videos", nargs="*", default=["/usr/share/doc/opencv-doc/examples/data/vtest.avi"])
    ap.add_argument("--model", default=str(ROOT / "models/movenet_multipose.onnx"))
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--max-side", type=int, nargs="*", default=[384, 512])
    args = ap.parse_args()
    ort_net, cv_net = MoveNet(args.model, "ort", 2), MoveNet(args.model, "cv2", 2)
    worst = {"features": 0.0, "heatmaps": 0.0}
    fp16 = 0.0
    print("| video | max:N | frame | features max abs diff | beliefs max abs diff | beliefs max | features max |")
    print("|---|---|---|---|---|---|---|")
    for v in args.videos:
        frames = read_frames(v, 200)
        for side in args.max_side:
            for i in np.linspace(0, len(frames) - 1, args.frames).round().astype(int):
                rgb = fit_input(frames[i], side)
                a, b = ort_net(rgb), cv_net(rgb)
                d = {k: float(np.abs(a[k] - b[k]).max()) for k in worst}
                for k in worst:
                    worst[k] = max(worst[k], d[k])
                    # The training cache stores the maps as float16 (cache.py): its rounding is the
                    # other difference between training-time and run-time inputs.
                    fp16 = max(fp16, float(np.abs(a[k].astype(np.float16).astype(np.float32) - b[k]).max()))
                print(f"| {pathlib.Path(v).name} | {side} | {i} | {d['features']:.2e} | {d['heatmaps']:.2e} "
                      f"| {float(a['heatmaps'].max()):.3f} | {float(a['features'].max()):.2f} |")
    print(f"worst onnxruntime vs OpenCV dnn: features {worst['features']:.2e}, beliefs {worst['heatmaps']:.2e}; "
          f"float16 cache vs OpenCV dnn (all maps): {fp16:.2e}")


if __name__ == "__main__":
    main()
