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
from torch import nn

from .model import NUM_JOINTS, TFFNet

OPSET = 10  # 10: Pad takes its pads as an attribute, which OpenCV 4.6 parses (11: a Reshape chain it rejects)


class PooledInput(nn.Module):
    """A grid_stride-2 TFFNet as it is exported: it takes the maps already averaged over 2x2 cells
    and returns the field on the maps' grid. The C++ runner pools the maps itself
    (tff_model.hpp), so that its camera warp moves a quarter of the cells and the engine gets a
    quarter of the input. The per-channel affine commutes with averaging: norm after the pool is
    the same function as the trained norm -> pool."""

    def __init__(self, model: TFFNet):
        super().__init__()
        self.model = model

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        m = self.model
        return m.up(m.pad(m.body(m.norm(x))))


def onnx_input(model: TFFNet, x: torch.Tensor) -> torch.Tensor:
    """The exported network's input for maps x on the full grid (pooled for grid_stride 2)."""
    return torch.nn.functional.avg_pool2d(x, 2) if model.grid_stride == 2 else x


def set_dims(value_info, dims) -> None:
    for d, v in zip(value_info.type.tensor_type.shape.dim, dims):
        d.Clear()
        if isinstance(v, int):
            d.dim_value = v
        else:
            d.dim_param = v


def export_onnx(model: TFFNet, path: str, metadata: dict | None = None) -> None:
    model = model.eval()
    c = 2 * (model.feature_channels + NUM_JOINTS)
    pooled = model.grid_stride == 2
    net = PooledInput(model) if pooled else model
    dummy = torch.zeros(1, c, 32 if pooled else 64, 32 if pooled else 64)
    buf = io.BytesIO()
    torch.onnx.export(net, dummy, buf, opset_version=OPSET, input_names=["input"],
                      output_names=["tff"], dynamic_axes={"input": {2: "h", 3: "w"}, "tff": {2: "H", 3: "W"}},
                      do_constant_folding=True)
    m = onnx.load_from_string(buf.getvalue())
    # The exporter names the spatial dims after its own shape inference; state the contract
    # explicitly: the field on the maps' grid H x W, the input on it (h = H) or pooled (h = H / 2).
    set_dims(m.graph.input[0], [1, c, "h", "w"])
    set_dims(m.graph.output[0], [1, 2 * NUM_JOINTS, "H", "W"])
    for node in m.graph.node:
        if node.op_type in ("Conv", "ConvTranspose") and not any(a.name == "kernel_shape" for a in node.attribute):
            raise RuntimeError(f"exported {node.op_type} {node.name} lacks kernel_shape (OpenCV 4.6 needs it)")
    m.doc_string = ("JointFlow Temporal Flow Field network (Doering et al., BMVC 2018, Sec. 3.2). input: "
                    "features(t-1), beliefs(t-1), features(t), beliefs(t) on the spatial model's grid H x W"
                    + (", averaged over 2x2 cells (h = H / 2, w = W / 2)" if pooled else " (h = H, w = W)")
                    + "; output tff: channel 2j = x, 2j+1 = y of COCO joint j, on the maps' grid H x W.")
    meta = dict(model.config())
    meta.update(metadata or {})
    for k, v in meta.items():
        e = m.metadata_props.add()
        e.key, e.value = str(k), v if isinstance(v, str) else json.dumps(v)
    onnx.checker.check_model(m)
    onnx.save(m, path)


def load_onnx(path: str) -> tuple[TFFNet, dict]:
    """A TFFNet holding the weights of an exported ONNX file, either form (the grid_stride-2 graph
    with the pool inside, as exported before the runner pooled, or without), and its metadata."""
    m = onnx.load(path)
    meta = {p.key: json.loads(p.value) if p.value[:1] in "0123456789[{" else p.value for p in m.metadata_props}
    model = TFFNet(int(meta["feature_channels"]), int(meta["width"]), int(meta["grid_stride"]))
    weights = {i.name.removeprefix("model."): torch.from_numpy(onnx.numpy_helper.to_array(i).copy())
               for i in m.graph.initializer}
    affine = [n for n in m.graph.node if n.op_type in ("Mul", "Add")][:2]  # the norm, first in the graph
    state = {k: v for k, v in weights.items() if k in model.state_dict()}
    state["norm.weight"] = weights[affine[0].input[1]].view(-1, 1, 1, 1)
    state["norm.bias"] = weights[affine[1].input[1]].view(-1)
    model.load_state_dict(state)
    for k in ("feature_channels", "width", "grid_stride"):
        meta.pop(k)
    return model.eval(), meta


def parity(model: TFFNet, path: str, hw=(40, 56), seed: int = 0) -> dict:
    """Max abs difference PyTorch vs onnxruntime and vs OpenCV dnn on one random input."""
    import cv2
    import onnxruntime as ort
    rng = np.random.default_rng(seed)
    c = 2 * (model.feature_channels + NUM_JOINTS)
    x = rng.uniform(0, 1, (1, c, *hw)).astype(np.float32)
    with torch.no_grad():
        ref = model.eval()(torch.from_numpy(x)).numpy()
        x = onnx_input(model, torch.from_numpy(x)).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    got_ort = sess.run(["tff"], {"input": x})[0]
    net = cv2.dnn.readNetFromONNX(path)
    net.setInput(x)
    got_cv = net.forward("tff")
    return dict(shape=list(ref.shape), ort=float(np.abs(got_ort - ref).max()),
                cv2=float(np.abs(got_cv - ref).max()), ref_max=float(np.abs(ref).max()))
