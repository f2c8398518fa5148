"""Python's overhead per frame over the C++ Tracker (issue 15's budget: under 2 % at 256x256).

Two measures in one run, on the same frames (vtest.avi scaled to 256x256, input size 256x256):
  * same call: the time of tracker.process(frame) seen from Python minus the time the same call
    spent inside the C++ Tracker::process (wrapping the array, releasing and taking the GIL,
    making the Pose objects and their keypoint arrays): no noise from one call to the next;
  * paired: tracker.process(frame) on tracker A against Tracker::process alone, timed in C++,
    on tracker B (the same settings, so the same state and work), alternating which goes first.
    On a loaded machine this one carries the noise of two calls.

    PYTHONPATH=build/python python3 bench/python_overhead.py [--frames N]
"""

import argparse
import statistics
import sys
import time

import cv2
import numpy as np

import jointflow

VTEST = "/usr/share/doc/opencv-doc/examples/data/vtest.avi"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--video", default=VTEST)
    parser.add_argument("--size", type=int, default=256)
    args = parser.parse_args()

    capture = cv2.VideoCapture(args.video)
    frames = []
    while len(frames) < args.frames:
        ok, frame = capture.read()
        if not ok:
            break
        frames.append(np.ascontiguousarray(cv2.resize(frame, (args.size, args.size),
                                                      interpolation=cv2.INTER_AREA)))
    if len(frames) < 20:
        sys.exit(f"python_overhead.py: could not read 20 frames of {args.video}")

    settings = dict(input_size=f"{args.size}x{args.size}")
    a = jointflow.Tracker(**settings)
    b = jointflow.Tracker(**settings)
    for frame in frames[:5]:  # warm-up: first runs allocate
        a.process(frame)
        b._process_seconds(frame)
    a.reset()
    b.reset()

    call, core, paired_py, paired_cpp, persons = [], [], [], [], []
    for i, frame in enumerate(frames):
        def python_side():
            start = time.perf_counter()
            poses = a.process(frame)
            elapsed = time.perf_counter() - start
            call.append(elapsed)
            core.append(a._core_seconds)
            paired_py.append(elapsed)
            persons.append(len(poses))

        def cpp_side():
            paired_cpp.append(b._process_seconds(frame))

        for side in ((python_side, cpp_side) if i % 2 == 0 else (cpp_side, python_side)):
            side()

    overhead = [c - k for c, k in zip(call, core)]
    med_core = statistics.median(core)
    same_call = statistics.median(overhead) / med_core
    paired = (statistics.median(paired_py) - statistics.median(paired_cpp)) / statistics.median(paired_cpp)
    print(f"frames: {len(frames)} at {args.size}x{args.size}, {statistics.mean(persons):.1f} "
          f"persons per frame, engine {a.engine}")
    print(f"C++ Tracker::process: median {med_core * 1e3:.2f} ms per frame")
    print(f"Python overhead, same call: median {statistics.median(overhead) * 1e6:.1f} us per "
          f"frame = {same_call * 100:.3f} % (mean {statistics.mean(overhead) * 1e6:.1f} us, "
          f"max {max(overhead) * 1e6:.1f} us)")
    print(f"Python overhead, paired against the C++ call on a second tracker: "
          f"{paired * 100:+.2f} % of the median")
    print(f"budget 2 %: {'met' if same_call < 0.02 else 'MISSED'}")


if __name__ == "__main__":
    main()
