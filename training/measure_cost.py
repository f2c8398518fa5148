#!/usr/bin/env python3
"""Run-time cost of a TFF ONNX file against the spatial network at the same input size, both on
OpenCV 4.6 dnn (the engine of the C++ runtime; Python binding 4.6.0.66), CPU. The two networks
are timed interleaved (A, B, A, B, ...) so that load from other processes hits both alike; the
table gives medians.

Usage: training/.venv/bin/python training/measure_cost.py TFF.onnx [--sizes 256x256 384x224 640x384]
"""
import argparse
import pathlib
import time

import cv2
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("tff")
    ap.add_argument("--spatial", default=str(ROOT / "models/movenet_multipose.onnx"))
    ap.add_argument("--sizes", nargs="*", default=["256x256", "384x224", "640x384"])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    cv2.setNumThreads(args.threads)
    spatial, tff = cv2.dnn.readNetFromONNX(args.spatial), cv2.dnn.readNetFromONNX(args.tff)
    rng = np.random.default_rng(0)
    print(f"| input WxH | grid | MoveNet ms | TFF ms | TFF / MoveNet |  (OpenCV {cv2.__version__}, "
          f"{args.threads} threads, median of {args.repeats})")
    print("|---|---|---|---|---|")
    for size in args.sizes:
        w, h = map(int, size.split("x"))
        img = rng.uniform(0, 255, (1, 3, h, w)).astype(np.float32)
        maps = rng.uniform(0, 1, (1, 82, h // 4, w // 4)).astype(np.float32)
        times = {"s": [], "t": []}
        for r in range(args.repeats + 2):
            for key, net, x in (("s", spatial, img), ("t", tff, maps)):
                t0 = time.perf_counter()
                net.setInput(x)
                net.forward()
                if r >= 2:  # the first runs allocate
                    times[key].append((time.perf_counter() - t0) * 1000)
        s, t = np.median(times["s"]), np.median(times["t"])
        print(f"| {w}x{h} | {w // 4}x{h // 4} | {s:.1f} | {t:.1f} | {t / s:.0%} |")


if __name__ == "__main__":
    main()
