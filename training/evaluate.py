#!/usr/bin/env python3
"""Held-out check of trained TFF ONNX files against the pose-only baselines: does the predicted
field tell true person correspondences from false ones?

On the held-out videos' cached pairs (no flips), per case (strides 1-4; "camera_motion": the
warped pairs, pans up to ~120 frame px, zoom, rotation; "reversed": camera-motion and stride-1-4
pairs played backwards; "crossing": pairs with two matched people whose boxes overlap), for every
confident person match (i in frame t, k in frame t+s; the chained pseudo-labels, dataset.py) with
at least one other candidate in frame t+s: is the true partner the one with the highest
similarity? Similarities:
  tff[:MODEL]       Psi = sum_j E_j (paper Eq. 8), E_j = E_aggr (Eq. 6, 10 samples, bilinear) for
                    joints that moved >= tau_delta frame pixels, 1 below (Eq. 7): the run time's
                    rule (core/association/joint_potentials.cpp), tau_delta in frame pixels;
  distance_rule     the same Psi on an all-zero field (what the tau_delta rule alone does);
  oks, iou          the geometric baselines (core/association/geometric_similarity.cpp).
Also the mean E_aggr of true and false joint pairs that moved >= tau_delta.

--tff-max-grid N runs each network as the C++ runner does with max_grid_side N (tff_model.hpp;
default 0, off): grids whose long side exceeds N are area-resampled to it, the field back.

Usage: training/.venv/bin/python training/evaluate.py [NAME=]MODEL.onnx [...] [--cache DIR]
           [--val STEM ...] [--tau-px 2] [--max-pairs 150] [--json OUT.json]
"""
import argparse
import json
import pathlib
import sys

import cv2
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.dataset import PairDataset  # noqa: E402
from jointflow_train.pseudo_labels import keypoint_box  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Held out from training, for the checks: the three of issue 6 and six more (the registry
# package's bikes.mp4 among them).
DEFAULT_VAL = ["yoloopencv_pedestrians", "mmaction2_test_video_structuralize", "violence_fight",
               "yolopeople_crowd", "yolov4deepsort_video", "mmaction2_demo", "mmpose_demo", "openpose_video",
               "bikes"]
COCO_SIGMAS = np.array([.026, .025, .025, .035, .035, .079, .079, .072, .072, .062, .062, .107, .107, .087, .087,
                        .089, .089], np.float32)


def bilinear(field: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """field [C, H, W] sampled at points (x, y), clamped to the grid like the C++ sampler."""
    c, h, w = field.shape
    x, y = np.clip(x, 0, w - 1), np.clip(y, 0, h - 1)
    x0, y0 = np.minimum(np.floor(x).astype(int), w - 1), np.minimum(np.floor(y).astype(int), h - 1)
    x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
    fx, fy = x - x0, y - y0
    top = field[:, y0, x0] * (1 - fx) + field[:, y0, x1] * fx
    bottom = field[:, y1, x0] * (1 - fx) + field[:, y1, x1] * fx
    return top * (1 - fy) + bottom * fy


def e_aggr(tff: np.ndarray, j: int, p: np.ndarray, q: np.ndarray, samples: int = 10) -> float:
    """Paper Eq. 6 on the grid (p, q in grid cells)."""
    d = q - p
    lam = float(np.hypot(*d))
    if not lam > 0:
        return 0.0
    o = np.linspace(0, 1, samples)
    pts = p[None] + o[:, None] * d[None]
    vec = bilinear(tff[2 * j:2 * j + 2], pts[:, 0], pts[:, 1])
    return float((vec.T @ (d / lam)).mean())


def oks(a, b, thr):
    common = (a[:, 2] >= thr) & (b[:, 2] >= thr)
    if not common.any():
        return 0.0
    area = 0.5 * sum(float(np.ptp(k[k[:, 2] >= thr, 0]) * np.ptp(k[k[:, 2] >= thr, 1])) for k in (a, b))
    d2 = ((a[:, :2] - b[:, :2]) ** 2).sum(1)
    k2 = (2 * COCO_SIGMAS) ** 2
    return float(np.exp(-d2[common] / (2 * max(area, 1e-9) * k2[common])).mean())


def box_iou(a, b, thr):
    ba, bb = keypoint_box(a, thr), keypoint_box(b, thr)
    ix = max(0.0, min(ba[2], bb[2]) - max(ba[0], bb[0]))
    iy = max(0.0, min(ba[3], bb[3]) - max(ba[1], bb[1]))
    union = (ba[2] - ba[0]) * (ba[3] - ba[1]) + (bb[2] - bb[0]) * (bb[3] - bb[1]) - ix * iy
    return ix * iy / union if union > 0 else 0.0


class Runner:
    """One TFF ONNX file on onnxruntime, optionally resampled to max_grid like the C++ runner."""

    def __init__(self, path: str, max_grid: int):
        import onnxruntime as ort
        self.sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
        self.max_grid = max_grid
        # The network's stride, as the C++ runner finds it: 2 when it takes the maps averaged over
        # 2x2 cells and returns the field on the maps' grid (the shipped form), 1 otherwise.
        c = self.sess.get_inputs()[0].shape[1]
        probe = self.sess.run(["tff"], {"input": np.zeros((1, c, 16, 16), np.float32)})[0]
        self.stride = probe.shape[2] // 16

    def __call__(self, x: np.ndarray) -> np.ndarray:
        c, h, w = x.shape
        s = self.max_grid / max(h, w) if self.max_grid and max(h, w) > self.max_grid else 1.0
        if s < 1:
            th, tw = max(2, int(round(h * s / 2)) * 2), max(2, int(round(w * s / 2)) * 2)
            small = np.stack([cv2.resize(ch, (tw, th), interpolation=cv2.INTER_AREA) for ch in x])
            out = self._run(small)
            return np.stack([cv2.resize(ch, (w, h), interpolation=cv2.INTER_LINEAR) for ch in out])
        return self._run(x)

    def _run(self, x):
        h, w = x.shape[1:]
        xin = np.pad(x, ((0, 0), (0, h % 2), (0, w % 2)))[None]
        if self.stride == 2:
            n, c, hh, ww = xin.shape
            xin = xin.reshape(n, c, hh // 2, 2, ww // 2, 2).mean(axis=(3, 5))
        return self.sess.run(["tff"], {"input": xin.astype(np.float32)})[0][0, :, :h, :w]


def cases(files, max_pairs):
    """(name, dataset, [(entry, reverse)])."""
    rng = np.random.default_rng(0)
    out = []
    for s in (1, 2, 3, 4):
        ds = PairDataset(files, strides=(s,), use_flips=False, use_warps=False)
        out.append((f"stride_{s}", ds, [(int(i), False) for i in rng.permutation(len(ds))[:max_pairs]]))
    ds = PairDataset(files, strides=(1, 2, 3, 4), use_flips=False, use_warps=True)
    warps = [i for i, e in enumerate(ds.entries) if e[0] == "warp"]
    plain = [i for i, e in enumerate(ds.entries) if e[0] == "pair"]
    out.append(("camera_motion", ds, [(i, False) for i in warps[:max_pairs]]))
    rev = list(rng.permutation(warps)[:max_pairs // 2]) + list(rng.permutation(plain)[:max_pairs - max_pairs // 2])
    out.append(("reversed", ds, [(int(i), True) for i in rev]))
    out.append(("crossing", ds, [(int(i), bool(k % 2)) for k, i in enumerate(rng.permutation(ds.crossing)[:max_pairs])]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("models", nargs="+")
    ap.add_argument("--cache", default=str(ROOT / "training/.cache/maps"))
    ap.add_argument("--val", nargs="*", default=DEFAULT_VAL)
    ap.add_argument("--tau-px", type=float, default=2.0, help="tau_delta in frame pixels (TrackerSettings)")
    ap.add_argument("--joint-threshold", type=float, default=0.3)
    ap.add_argument("--max-pairs", type=int, default=150)
    ap.add_argument("--tff-max-grid", type=int, default=0,
                    help="as the C++ runner's max_grid_side (0: the network on the full grid)")
    ap.add_argument("--json", default="")
    args = ap.parse_args()
    runners = {}
    for m in args.models:  # NAME=PATH or PATH (named after the file)
        name, _, path = m.rpartition("=")
        runners[name or pathlib.Path(path).stem] = Runner(path, args.tff_max_grid)
    files = [str(pathlib.Path(args.cache) / f"{s}.npz") for s in args.val]
    files = [f for f in files if pathlib.Path(f).exists()]
    if not files:
        sys.exit(f"none of the held-out videos {args.val} is cached in {args.cache}")
    names = [f"tff:{n}" for n in runners] + ["distance_rule", "oks", "iou"]
    results = {}
    thr = args.joint_threshold
    for case, ds, pairs in cases(files, args.max_pairs):
        correct = {n: 0 for n in names}
        e_true = {n: [] for n in runners}
        e_false = {n: [] for n in runners}
        persons = 0
        for i, rev in pairs:
            x, _, _, _, (kps_a, kps_b, matches) = ds.example(i, rev)
            if not matches or len(kps_b) < 2:
                continue
            v = ds.videos[ds.entries[i][1]]
            tau_cells = args.tau_px / v.pixels_per_cell()
            fields = {n: r(x) for n, r in runners.items()}
            for a_i, b_k in matches:
                a = kps_a[a_i]
                score = {n: [] for n in names}
                for k, b in enumerate(kps_b):
                    both = (a[:, 2] >= thr) & (b[:, 2] >= thr)
                    moved = np.hypot(*(b[:, :2] - a[:, :2]).T) >= tau_cells
                    for n, f in fields.items():
                        psi = 0.0
                        for j in np.nonzero(both)[0]:
                            if moved[j]:
                                e = e_aggr(f, j, a[j, :2], b[j, :2])
                                psi += e
                                (e_true if k == b_k else e_false)[n].append(e)
                            else:
                                psi += 1.0
                        score[f"tff:{n}"].append(psi)
                    score["distance_rule"].append(float((both & ~moved).sum()))
                    score["oks"].append(oks(a, b, thr))
                    score["iou"].append(box_iou(a, b, thr))
                persons += 1
                for n, vals in score.items():
                    vals = np.array(vals)
                    correct[n] += int(vals[b_k] > np.delete(vals, b_k).max())
        results[case] = dict(
            pairs=len(pairs), persons=persons,
            accuracy={n: round(c / max(persons, 1), 3) for n, c in correct.items()},
            mean_E_aggr_moving_true={n: round(float(np.mean(v)), 3) if v else None for n, v in e_true.items()},
            mean_E_aggr_moving_false={n: round(float(np.mean(v)), 3) if v else None for n, v in e_false.items()})
        print(f"{case}: {json.dumps(results[case])}", flush=True)
    # A Markdown table: person accuracy per case and similarity.
    print("\n| case | persons | " + " | ".join(names) + " |")
    print("|---|---:|" + "---:|" * len(names))
    for case, r in results.items():
        print(f"| {case} | {r['persons']} | " + " | ".join(f"{r['accuracy'][n]:.3f}" for n in names) + " |")
    out = dict(models=args.models, held_out=args.val, tau_px=args.tau_px, tff_max_grid=args.tff_max_grid,
               results=results)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
