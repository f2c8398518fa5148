#!/usr/bin/env python3
"""Held-out check of a trained TFF ONNX file: does the predicted field tell true joint
correspondences from false ones?

On the held-out videos' cached pairs (no flips; strides 1-3, and their camera-motion warps), for every confident,
unambiguous person match (i in frame t, k in frame t+s; the pseudo-labels) and every joint j
confident in both frames:
  true pair:  E_j(p_(j,i)^t, p_(j,k)^(t+s))    false pairs: the same joint of every other person k'
with E_j = E_aggr (paper Eq. 6, line integral of T_j along the segment, 10 samples, bilinear)
for Delta >= tau_Delta, and 1 below (Eq. 7). Person level: the fraction of matched persons i
(with at least one other candidate in frame t+s) whose true partner has the highest
Psi = sum_j E_j (Eq. 8), compared with the same rule on an all-zero field (only the tau_Delta
distance rule), which shows what the network adds.

Usage: training/.venv/bin/python training/evaluate.py MODEL.onnx [--cache DIR] [--val STEM ...]
"""
import argparse
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.dataset import PairDataset  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_VAL = ["yoloopencv_pedestrians", "mmaction2_test_video_structuralize", "violence_fight"]


def bilinear(field: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """field [C, H, W] sampled at points (x, y); 0 outside the grid."""
    c, h, w = field.shape
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    out = np.zeros((c, len(x)), np.float32)
    for dx in (0, 1):
        for dy in (0, 1):
            xi, yi = x0 + dx, y0 + dy
            wgt = (1 - np.abs(x - xi)) * (1 - np.abs(y - yi))
            ok = (xi >= 0) & (xi < w) & (yi >= 0) & (yi < h)
            out[:, ok] += field[:, yi[ok], xi[ok]] * wgt[ok]
    return out


def joint_energy(tff: np.ndarray, j: int, p: np.ndarray, q: np.ndarray, tau: float, samples: int = 10) -> float:
    """E_j of paper Eq. 7 with E_aggr of Eq. 6."""
    d = q - p
    lam = float(np.hypot(*d))
    if lam < tau:
        return 1.0
    o = np.linspace(0, 1, samples)
    pts = p[None] + o[:, None] * d[None]
    vec = bilinear(tff[2 * j:2 * j + 2], pts[:, 0], pts[:, 1])
    return float((vec.T @ (d / lam)).mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model")
    ap.add_argument("--cache", default=str(ROOT / "training/.cache/maps"))
    ap.add_argument("--val", nargs="*", default=DEFAULT_VAL)
    ap.add_argument("--tau", type=float, default=2.0, help="tau_Delta in grid cells (paper: 2)")
    ap.add_argument("--joint-threshold", type=float, default=0.3)
    ap.add_argument("--max-pairs", type=int, default=400)
    args = ap.parse_args()
    import onnxruntime as ort
    sess = ort.InferenceSession(args.model, providers=["CPUExecutionProvider"])
    files = [str(pathlib.Path(args.cache) / f"{s}.npz") for s in args.val]
    files = [f for f in files if pathlib.Path(f).exists()]
    if not files:
        sys.exit(f"none of the held-out videos {args.val} is cached in {args.cache}")
    results = {}
    for stride in (1, 2, 3, "camera_motion"):
        if stride == "camera_motion":  # the held-out videos' warped pairs (strides 1-3 + affine)
            ds = PairDataset(files, strides=(1, 2, 3), use_flips=False, use_warps=True)
            idx = [i for i, e in enumerate(ds.entries) if e[0] == "warp"][:args.max_pairs]
        else:
            ds = PairDataset(files, strides=(stride,), use_flips=False, use_warps=False)
            idx = np.random.default_rng(0).permutation(len(ds))[:args.max_pairs]
        true_e, false_e, moving_true, moving_false = [], [], [], []
        correct = {"tff": 0, "distance_rule_only": 0}
        persons = 0
        for i in idx:
            x, _, _, _, (kps_a, kps_b, matches) = ds.example(int(i))
            if not matches:
                continue
            h, w = x.shape[1:]
            xin = np.pad(x, ((0, 0), (0, h % 2), (0, w % 2)))[None]
            tff = sess.run(["tff"], {"input": xin})[0][0, :, :h, :w]
            zero = np.zeros_like(tff)
            for a_i, b_k in matches:
                a = kps_a[a_i]
                psi = {"tff": [], "distance_rule_only": []}
                for k, b in enumerate(kps_b):
                    s_t, s_z = 0.0, 0.0
                    for j in range(17):
                        if a[j, 2] < args.joint_threshold or b[j, 2] < args.joint_threshold:
                            continue
                        e = joint_energy(tff, j, a[j, :2], b[j, :2], args.tau)
                        s_t += e
                        s_z += joint_energy(zero, j, a[j, :2], b[j, :2], args.tau)
                        moving = np.hypot(*(b[j, :2] - a[j, :2])) >= args.tau
                        (true_e if k == b_k else false_e).append(e)
                        if moving:
                            (moving_true if k == b_k else moving_false).append(e)
                    psi["tff"].append(s_t)
                    psi["distance_rule_only"].append(s_z)
                if len(kps_b) > 1:
                    persons += 1
                    for name, v in psi.items():
                        v = np.array(v)
                        correct[name] += int(v[b_k] > np.delete(v, b_k).max())
        results[f"stride_{stride}" if stride != "camera_motion" else stride] = dict(
            pairs=len(idx), persons_with_alternatives=persons,
            person_accuracy={k: round(c / max(persons, 1), 4) for k, c in correct.items()},
            mean_E_true=round(float(np.mean(true_e)), 4) if true_e else None,
            mean_E_false=round(float(np.mean(false_e)), 4) if false_e else None,
            moving_joints_true=len(moving_true), mean_E_aggr_true_moving=round(float(np.mean(moving_true)), 4) if moving_true else None,
            moving_joints_false=len(moving_false), mean_E_aggr_false_moving=round(float(np.mean(moving_false)), 4) if moving_false else None)
        print(f"{stride}: {json.dumps(list(results.values())[-1])}", flush=True)
    print(json.dumps(dict(model=args.model, held_out=args.val, tau_cells=args.tau, results=results), indent=2))


if __name__ == "__main__":
    main()
