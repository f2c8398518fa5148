#!/usr/bin/env python3
"""Run-time cost of a TFF ONNX file against the spatial network at the same input size, both on
OpenCV 4.6 dnn (the engine of the C++ runtime; Python binding 4.6.0.66), CPU. The two networks
are timed interleaved (A, B, A, B, ...) so that load from other processes hits both alike; the
table gives medians.

The TFF side is timed as the C++ runner runs it (core/temporal/tff_model.cpp): by default on the
spatial grid itself (a network of stride 2, the shipped form, on the maps averaged over 2x2 cells,
its field on the spatial grid); with --max-grid N (TemporalFlowModel's max_grid_side) grids whose long side
exceeds N are resampled to it per channel (cv2.resize, INTER_AREA), the network runs there and the
field is resized back (INTER_LINEAR), both resizes inside the TFF time.

Usage: training/.venv/bin/python training/measure_cost.py TFF.onnx [--sizes 256x256 640x384 960x544]
           [--max-grid N]
Sizes are MoveNet input sizes: 256x256, max:640 of a 16:9 frame (640x384 after padding to 32) and
the Bonn sequence's native 960x540 (960x544).
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
    ap.add_argument("--sizes", nargs="*", default=["256x256", "640x384", "960x544"])
    ap.add_argument("--max-grid", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    cv2.setNumThreads(args.threads)
    spatial, tff = cv2.dnn.readNetFromONNX(args.spatial), cv2.dnn.readNetFromONNX(args.tff)
    rng = np.random.default_rng(0)
    tff.setInput(np.zeros((1, 82, 16, 16), np.float32))
    stride = tff.forward().shape[2] // 16  # 2: takes the maps pooled 2x2 (tff_model.hpp)
    print(f"| input WxH | grid | TFF network grid | MoveNet ms | TFF ms | TFF / MoveNet |  (OpenCV {cv2.__version__}, "
          f"{args.threads} threads, median of {args.repeats})")
    print("|---|---|---|---|---|---|")
    for size in args.sizes:
        w, h = map(int, size.split("x"))
        img = rng.uniform(0, 255, (1, 3, h, w)).astype(np.float32)
        gh, gw = h // 4, w // 4
        maps = rng.uniform(0, 1, (82, gh, gw)).astype(np.float32)
        scale = args.max_grid / max(gh, gw) if args.max_grid and max(gh, gw) > args.max_grid else 1.0
        fh, fw = (max(2, 2 * round(gh * scale / 2)), max(2, 2 * round(gw * scale / 2))) if scale < 1 else (gh, gw)
        nh, nw = fh // stride, fw // stride  # the network's input grid

        def run_spatial():
            spatial.setInput(img)
            spatial.forward()

        def run_tff():
            x = maps
            if (nh, nw) != (gh, gw):  # this frame's maps; the runner keeps the previous frame's resampled
                half = np.stack([cv2.resize(c, (nw, nh), interpolation=cv2.INTER_AREA) for c in maps[:41]])
                x = np.concatenate([half, half])
            tff.setInput(x[None])
            out = tff.forward()[0]
            if (fh, fw) != (gh, gw):
                np.stack([cv2.resize(c, (gw, gh), interpolation=cv2.INTER_LINEAR) for c in out])

        times = {"s": [], "t": []}
        for r in range(args.repeats + 2):
            for key, fn in (("s", run_spatial), ("t", run_tff)):
                t0 = time.perf_counter()
                fn()
                if r >= 2:  # the first runs allocate
                    times[key].append((time.perf_counter() - t0) * 1000)
        s, t = np.median(times["s"]), np.median(times["t"])
        print(f"| {w}x{h} | {gw}x{gh} | {nw}x{nh} | {s:.1f} | {t:.1f} | {t / s:.0%} |")


if __name__ == "__main__":
    main()
