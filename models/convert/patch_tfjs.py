#!/usr/bin/env python3
"""Repair the two known defects of the tfjs graph-model JSON files before tf2onnx reads them.

1. `_FusedConv2D` nodes lack the `TArgs` attribute (tf2onnx issue 2214). TensorFlow's op
   definition requires it; its value is the element type `T` repeated `num_args` times.
2. Some nodes (e.g. `TopKV2`) lack attributes that were added to the op definition after the
   model was exported (`index_type`). Every attribute that TensorFlow's op registry gives a
   default value is filled in with that default when it is missing.

Usage: patch_tfjs.py IN.json OUT.json   (the weight shards are linked next to OUT.json)
"""
import json
import os
import sys

from google.protobuf import json_format
from tensorflow.python.framework import op_def_registry


def patch_nodes(nodes):
    fixed = {"TArgs": 0, "defaults": 0}
    for node in nodes:
        attrs = node.setdefault("attr", {})
        op = node["op"]
        if op == "_FusedConv2D" and "TArgs" not in attrs:
            num_args = int(attrs.get("num_args", {}).get("i", "0"))
            elem = attrs["T"]["type"]
            attrs["TArgs"] = {"list": {"type": [elem] * num_args}}
            fixed["TArgs"] += 1
        op_def = op_def_registry.get(op)
        if op_def is None:
            continue  # tfjs-only ops such as FusedDepthwiseConv2dNative
        for a in op_def.attr:
            if a.name in attrs or not a.HasField("default_value"):
                continue
            attrs[a.name] = json_format.MessageToDict(a.default_value)
            fixed["defaults"] += 1
    return fixed


def main():
    src, dst = sys.argv[1], sys.argv[2]
    with open(src) as f:
        model = json.load(f)
    topo = model["modelTopology"]
    fixed = patch_nodes(topo.get("node", []))
    for fn in topo.get("library", {}).get("function", []):
        for k, v in patch_nodes(fn.get("nodeDef", [])).items():
            fixed[k] += v
    os.makedirs(os.path.dirname(os.path.abspath(dst)), exist_ok=True)
    with open(dst, "w") as f:
        json.dump(model, f)
    src_dir = os.path.dirname(os.path.abspath(src))
    dst_dir = os.path.dirname(os.path.abspath(dst))
    for group in model["weightsManifest"]:
        for shard in group["paths"]:
            link = os.path.join(dst_dir, shard)
            if not os.path.exists(link):
                os.symlink(os.path.join(src_dir, shard), link)
    print(f"{os.path.basename(src)}: added TArgs to {fixed['TArgs']} nodes, "
          f"{fixed['defaults']} default attributes")


if __name__ == "__main__":
    main()
