#!/usr/bin/env python3
"""Exports a training checkpoint (train.py's checkpoint.pt) to ONNX and prints the parity check.

The source may also be a TFF ONNX file exported before: its weights and metadata are written
again in the current export form (models/README.md, "tff_movenet.onnx": how the shipped file was
brought to the pooled input).

Usage: training/.venv/bin/python training/export_checkpoint.py RUN/checkpoint.pt|OLD.onnx OUT.onnx
"""
import json
import pathlib
import sys

import torch

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.export import export_onnx, load_onnx, parity  # noqa: E402
from jointflow_train.model import TFFNet  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    if sys.argv[1].endswith(".onnx"):
        model, meta = load_onnx(sys.argv[1])
        export_onnx(model, sys.argv[2], meta)
        print(json.dumps(parity(model, sys.argv[2])))
        return
    ck = torch.load(sys.argv[1], map_location="cpu", weights_only=False)
    model = TFFNet(**ck["config"])
    model.load_state_dict(ck["state"])
    export_onnx(model, sys.argv[2], dict(spatial_model="movenet_multipose", grid="MoveNet stride-4 grid",
                                         sigma=1.0, steps=ck.get("step", ck["args"]["steps"])))
    print(json.dumps(parity(model, sys.argv[2])))


if __name__ == "__main__":
    main()
