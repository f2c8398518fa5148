"""onnxruntime's forward time on an ONNX file, for jointflow-bench's engine comparison.

    python ort_time.py MODEL.onnx

A server, so that jointflow-bench can take turns between the engines run by run (each run of
each engine then sees the same machine load): prints {"ort_version": ...} once, then for each
line "HEIGHT WIDTH THREADS" on stdin runs the model once on that input and prints one JSON line
{"ms": the run's time}. A session per (height, width, threads), made on its first line with 3
warm-up runs (allocation at this size). Input: the same kind jointflow-bench gives cv::dnn and
OpenVINO (uniform random values of the model's input range, float32 NCHW); every graph output is
fetched.
"""
import json
import sys
import time

import numpy as np
import onnxruntime as ort


def main() -> None:
    model = sys.argv[1]
    print(json.dumps({"ort_version": ort.__version__}), flush=True)
    sessions = {}
    rng = np.random.default_rng(0)
    for line in sys.stdin:
        height, width, threads = map(int, line.split())
        key = (height, width, threads)
        if key not in sessions:
            options = ort.SessionOptions()
            options.intra_op_num_threads = threads
            options.inter_op_num_threads = 1
            options.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
            session = ort.InferenceSession(model, options, providers=["CPUExecutionProvider"])
            inp = session.get_inputs()[0]
            channels = inp.shape[1] if isinstance(inp.shape[1], int) else 3
            # MoveNet takes 0..255; PoseNet [-1, 1]: the input the model documents.
            low, high = (-1.0, 1.0) if inp.name == "image" else (0.0, 255.0)
            x = rng.uniform(low, high, size=(1, channels, height, width)).astype(np.float32)
            outputs = [o.name for o in session.get_outputs()]
            for _ in range(3):
                session.run(outputs, {inp.name: x})
            sessions[key] = (session, outputs, {inp.name: x})
        session, outputs, feed = sessions[key]
        t0 = time.perf_counter()
        session.run(outputs, feed)
        print(json.dumps({"ms": (time.perf_counter() - t0) * 1000.0}), flush=True)


if __name__ == "__main__":
    main()
