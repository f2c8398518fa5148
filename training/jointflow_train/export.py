"""ONNX export of the TFF network in a form OpenCV 4.6 dnn runs, and parity checks.

OpenCV 4.6 needs: explicit kernel_shape on every Conv (torch writes it), opset <= 11, declared
output shapes (symbolic H, W are fine), constant channel counts (shared/notes/models.md).
"""
from __future__ import annotations

import io
import json

import numpy as np
import onnx
import torch

from .model import NUM_JOINTS, TFFNet

OPSET = 10  # 10: Pad takes its pads as an attribute, which OpenCV 4.6 parses (11: a Reshape chain it rejects)


def export_onnx(model: TFFNet, path: str, metadata: dict | None = None) -> None:
    model = model.eval()
    c = 2 * (model.feature_channels + NUM_JOINTS)
    dummy = torch.zeros(1, c, 64, 64)
    buf = io.BytesIO()
    torch.onnx.export(model, dummy, buf, opset_version=OPSET, input_names=["input"],
                      output_names=["tff"], dynamic_axes={"input": {2: "H", 3: "W"}, "tff": {2: "H", 3: "W"}},
                      do_constant_folding=True)
    m = onnx.load_from_string(buf.getvalue())
    # The exporter names the output's spatial dims after its own shape inference; state the
    # contract (same grid as the input) explicitly.
    dims = m.graph.output[0].type.tensor_type.shape.dim
    for d, v in zip(dims, [1, 2 * NUM_JOINTS, "H", "W"]):
        d.Clear()
        if isinstance(v, int):
            d.dim_value = v
        else:
            d.dim_param = v
    for node in m.graph.node:
        if node.op_type in ("Conv", "ConvTranspose") and not any(a.name == "kernel_shape" for a in node.attribute):
            raise RuntimeError(f"exported {node.op_type} {node.name} lacks kernel_shape (OpenCV 4.6 needs it)")
    m.doc_string = ("JointFlow Temporal Flow Field network (Doering et al., BMVC 2018, Sec. 3.2). input: "
                    "features(t-1), beliefs(t-1), features(t), beliefs(t) on the spatial model's grid; "
                    "output tff: channel 2j = x, 2j+1 = y of COCO joint j, same grid.")
    meta = dict(model.config())
    meta.update(metadata or {})
    for k, v in meta.items():
        e = m.metadata_props.add()
        e.key, e.value = str(k), v if isinstance(v, str) else json.dumps(v)
    onnx.checker.check_model(m)
    onnx.save(m, path)


def parity(model: TFFNet, path: str, hw=(40, 56), seed: int = 0) -> dict:
    """Max abs difference PyTorch vs onnxruntime and vs OpenCV dnn on one random input."""
    import cv2
    import onnxruntime as ort
    rng = np.random.default_rng(seed)
    c = 2 * (model.feature_channels + NUM_JOINTS)
    x = rng.uniform(0, 1, (1, c, *hw)).astype(np.float32)
    with torch.no_grad():
        ref = model.eval()(torch.from_numpy(x)).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    got_ort = sess.run(["tff"], {"input": x})[0]
    net = cv2.dnn.readNetFromONNX(path)
    net.setInput(x)
    got_cv = net.forward("tff")
    return dict(shape=list(ref.shape), ort=float(np.abs(got_ort - ref).max()),
                cv2=float(np.abs(got_cv - ref).max()), ref_max=float(np.abs(ref).max()))
