"""onnxruntime's forward time on an ONNX file, for jointflow-bench's cv::dnn comparison.

    python ort_time.py MODEL.onnx HEIGHT WIDTH THREADS RUNS

Feeds the same kind of input jointflow-bench gives cv::dnn (uniform random values of the model's
input range, float32 NCHW), runs every graph output, and prints one JSON line:
{"ort_ms": median ms per run, "ort_version": ..., "threads": ...}.
"""
import json
import statistics
import sys
import time

import numpy as np
import onnxruntime as ort


def main() -> None:
    model, height, width, threads, runs = sys.argv[1], *map(int, sys.argv[2:6])
    options = ort.SessionOptions()
    options.intra_op_num_threads = threads
    options.inter_op_num_threads = 1
    options.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
    session = ort.InferenceSession(model, options, providers=["CPUExecutionProvider"])
    inp = session.get_inputs()[0]
    channels = inp.shape[1] if isinstance(inp.shape[1], int) else 3
    rng = np.random.default_rng(0)
    # MoveNet takes 0..255; PoseNet [-1, 1]: scale to the input the model documents.
    low, high = (-1.0, 1.0) if inp.name == "image" else (0.0, 255.0)
    x = rng.uniform(low, high, size=(1, channels, height, width)).astype(np.float32)
    outputs = [o.name for o in session.get_outputs()]
    for _ in range(3):  # warm-up: allocation at this size
        session.run(outputs, {inp.name: x})
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        session.run(outputs, {inp.name: x})
        times.append((time.perf_counter() - t0) * 1000.0)
    print(json.dumps({"ort_ms": statistics.median(times), "ort_version": ort.__version__,
                      "threads": threads}))


if __name__ == "__main__":
    main()
