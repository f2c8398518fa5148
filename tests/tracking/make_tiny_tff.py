#!/usr/bin/env python3
"""Writes the tiny TFF networks the tracking tests run (tests/data/tff_*.onnx, a few KB each).

Run with the models' venv (it has the `onnx` package):
    models/convert/.venv/bin/python tests/tracking/make_tiny_tff.py

All use the TFF channel contract (models/README.md) for a spatial model with C = 3 feature
channels: input "input" [1, 2*(3+17) = 40, H, W] = features(t-1), beliefs(t-1), features(t),
beliefs(t); output "tff" [1, 34, H, W].
  tff_tiny_c3.onnx        the paper's architecture (five 7x7 convolutions, stride 1, then two 1x1,
                          ReLU after each but the last, which must give signed vectors), 2 channels
                          wide, fixed random weights; tff_tiny_c3_expected.json holds its output on
                          a known input, computed here with numpy.
  tff_wiring_c3.onnx      one 1x1 convolution with fixed weights whose output tells which input
                          channel went where: tff[2j] = beliefs(t)[j] + 10 * features(t)[j % 3],
                          tff[2j+1] = beliefs(t-1)[j] + 10 * features(t-1)[j % 3].
  tff_bad_output_c3.onnx  like the wiring model but with 17 output channels (must be refused).
  tff_wiring_c24.onnx     the wiring model for MoveNet's 24 feature channels (82 input channels),
                          to run the whole Tracker with the "tff" similarity.
  tff_wiring_stride2_c3.onnx  the wiring model, then each cell copied to 2x2 (ConvTranspose, kernel 2,
                          stride 2, weights 1): a network of stride 2 like the shipped one, whose
                          input is the maps averaged over 2x2 cells and whose field comes on the
                          maps' grid [1, 34, 2h, 2w].
"""
import json
import pathlib

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

C = 3
J = 17
OUT = 2 * J
DATA = pathlib.Path(__file__).resolve().parents[1] / "data"


def graph(layers, out_channels, name, c=C, stride=1):
    """layers: list of (weight [O, I, k, k], bias [O], relu); stride 2 appends a 2x2 copy of each
    output cell."""
    nodes, inits = [], []
    x = "input"
    for i, (w, b, relu) in enumerate(layers):
        k = w.shape[2]
        inits += [numpy_helper.from_array(w.astype(np.float32), f"w{i}"),
                  numpy_helper.from_array(b.astype(np.float32), f"b{i}")]
        y = "tff" if (i == len(layers) - 1 and stride == 1) else f"conv{i}"
        conv_out = y if not relu else f"pre{i}"
        nodes.append(helper.make_node("Conv", [x, f"w{i}", f"b{i}"], [conv_out],
                                      kernel_shape=[k, k], pads=[k // 2] * 4, strides=[1, 1]))
        if relu:
            nodes.append(helper.make_node("Relu", [conv_out], [y]))
        x = y
    if stride == 2:
        inits.append(numpy_helper.from_array(np.ones((out_channels, 1, 2, 2), np.float32), "up"))
        nodes.append(helper.make_node("ConvTranspose", [x, "up"], ["tff"], kernel_shape=[2, 2],
                                      strides=[2, 2], group=out_channels))
    g = helper.make_graph(
        nodes, name,
        [helper.make_tensor_value_info("input", TensorProto.FLOAT,
                                       [1, 2 * (c + J)] + (["H", "W"] if stride == 1 else ["h", "w"]))],
        [helper.make_tensor_value_info("tff", TensorProto.FLOAT, [1, out_channels, "H", "W"])],
        inits)
    m = helper.make_model(g, opset_imports=[helper.make_opsetid("", 11)],
                          producer_name="jointflow-tests")
    m.ir_version = 6
    onnx.checker.check_model(m)
    return m


def conv_numpy(x, w, b):
    """Same-padded stride-1 convolution of x [I, H, W] with w [O, I, k, k]."""
    k = w.shape[2]
    p = k // 2
    xp = np.pad(x, ((0, 0), (p, p), (p, p)))
    h, wd = x.shape[1:]
    out = np.zeros((w.shape[0], h, wd), np.float64)
    for dy in range(k):
        for dx in range(k):
            out += np.einsum("oi,ihw->ohw", w[:, :, dy, dx], xp[:, dy:dy + h, dx:dx + wd])
    return out + b[:, None, None]


def test_input(h, w):
    c, y, x = np.meshgrid(np.arange(2 * (C + J)), np.arange(h), np.arange(w), indexing="ij")
    return (0.5 + 0.5 * np.sin(0.7 * c + 0.3 * y + 0.2 * x)).astype(np.float32)


def main():
    rng = np.random.default_rng(2018)
    width = 2
    layers = []
    channels = 2 * (C + J)
    for _ in range(5):
        layers.append((rng.normal(0, 0.05, (width, channels, 7, 7)), rng.normal(0, 0.1, width), True))
        channels = width
    layers.append((rng.normal(0, 0.5, (width, width, 1, 1)), rng.normal(0, 0.1, width), True))
    layers.append((rng.normal(0, 0.5, (OUT, width, 1, 1)), rng.normal(0, 0.1, OUT), False))
    onnx.save(graph(layers, OUT, "tff_tiny"), DATA / "tff_tiny_c3.onnx")

    h, w = 6, 5
    x = test_input(h, w).astype(np.float64)
    for wt, b, relu in layers:
        x = conv_numpy(x, wt.astype(np.float32).astype(np.float64), b.astype(np.float32))
        if relu:
            x = np.maximum(x, 0)
    expected = {"height": h, "width": w, "feature_channels": C,
                "input": "0.5 + 0.5 * sin(0.7 c + 0.3 y + 0.2 x), c the contract channel",
                "tff": np.round(x, 7).reshape(-1).tolist()}
    (DATA / "tff_tiny_c3_expected.json").write_text(json.dumps(expected))

    def wiring(c):
        w = np.zeros((OUT, 2 * (c + J), 1, 1))
        prev_feat, prev_bel, cur_feat, cur_bel = 0, c, c + J, 2 * c + J
        for j in range(J):
            w[2 * j, cur_bel + j] = 1
            w[2 * j, cur_feat + j % c] = 10
            w[2 * j + 1, prev_bel + j] = 1
            w[2 * j + 1, prev_feat + j % c] = 10
        return w

    w3 = wiring(C)
    onnx.save(graph([(w3, np.zeros(OUT), False)], OUT, "tff_wiring"), DATA / "tff_wiring_c3.onnx")
    onnx.save(graph([(w3[:J], np.zeros(J), False)], J, "tff_bad_output"),
              DATA / "tff_bad_output_c3.onnx")
    onnx.save(graph([(wiring(24), np.zeros(OUT), False)], OUT, "tff_wiring", c=24),
              DATA / "tff_wiring_c24.onnx")
    onnx.save(graph([(w3, np.zeros(OUT), False)], OUT, "tff_wiring_stride2", stride=2),
              DATA / "tff_wiring_stride2_c3.onnx")

if __name__ == "__main__":
    main()
