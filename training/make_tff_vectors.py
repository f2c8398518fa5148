#!/usr/bin/env python3
"""Writes tests/data/tff_render_vectors.json: TFF renderings (paper Eq. 2-4) from the Python
renderer, which tests/training/test_tff_vectors.cpp compares with the C++ renderer.

Cases: hand-picked edge cases (axis-aligned and diagonal motions with cells exactly on the
inclusive boundary of Omega, zero motion, overlapping people averaged by n(p), motions leaving the
grid, sigma != 1) plus seeded random ones. Random motions with a cell within 1e-4 of the boundary
of Omega are redrawn: there float rounding order (e.g. FMA in C++) could flip membership, which is
not a disagreement about the definition.

Usage: training/.venv/bin/python training/make_tff_vectors.py [--out tests/data/tff_render_vectors.json]
"""
import argparse
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.tff_render import render_tff  # noqa: E402

NUM_JOINTS = 17


def near_boundary(motions, grid_hw, sigma, eps=1e-4):
    h, w = grid_hw
    cols = np.arange(w, dtype=np.float64)[None, :]
    rows = np.arange(h, dtype=np.float64)[:, None]
    for _, f, t in motions:
        d = np.array(t, np.float64) - np.array(f, np.float64)
        lam = np.hypot(*d)
        if lam == 0:
            continue
        v = d / lam
        along = v[0] * (cols - f[0]) + v[1] * (rows - f[1])
        across = np.abs(-v[1] * (cols - f[0]) + v[0] * (rows - f[1]))
        inside_strip = across <= sigma + eps
        inside_len = (along >= -eps) & (along <= lam + eps)
        if (np.any(np.abs(along) < eps) or np.any(np.abs(along - lam) < eps)) and np.any(inside_strip):
            return True
        if np.any((np.abs(across - sigma) < eps) & inside_len):
            return True
    return False


def random_case(rng, idx):
    h, w = int(rng.integers(4, 24)), int(rng.integers(4, 24))
    sigma = float(rng.choice([1.0, 1.0, 0.5, 1.5, 2.0]))
    while True:
        motions = []
        for _ in range(int(rng.integers(1, 8))):
            j = int(rng.integers(0, NUM_JOINTS))
            f = rng.uniform(-2, [w + 1, h + 1]).astype(np.float32)
            t = (f + rng.normal(0, 4, 2)).astype(np.float32)
            motions.append((j, [float(f[0]), float(f[1])], [float(t[0]), float(t[1])]))
        if not near_boundary(motions, (h, w), sigma):
            return dict(name=f"random_{idx}", grid=[w, h], sigma=sigma, motions=motions)


def edge_cases():
    """Hand-picked cases. Axis-aligned motions between integer points put cells exactly on the
    inclusive boundary of Omega (exact in float); the oblique ones keep every cell clear of it."""
    return [
        dict(name="horizontal_inclusive_ends_and_width", grid=[10, 7], sigma=1.0,
             motions=[(0, [2.0, 3.0], [6.0, 3.0])]),
        dict(name="vertical_up", grid=[6, 9], sigma=1.0, motions=[(5, [3.0, 7.0], [3.0, 1.0])]),
        dict(name="diagonal", grid=[12, 12], sigma=1.0, motions=[(9, [1.25, 0.75], [9.4, 8.8])]),
        dict(name="zero_motion_contributes_nothing", grid=[5, 5], sigma=1.0,
             motions=[(3, [2.0, 2.0], [2.0, 2.0])]),
        dict(name="two_people_opposite_directions_average", grid=[10, 5], sigma=1.0,
             motions=[(16, [1.0, 2.0], [8.0, 2.0]), (16, [8.0, 2.0], [1.0, 2.0])]),
        dict(name="two_people_crossing_average", grid=[11, 11], sigma=1.0,
             motions=[(10, [0.0, 5.0], [10.0, 5.0]), (10, [5.0, 0.0], [5.0, 10.0])]),
        dict(name="partly_outside_grid", grid=[6, 6], sigma=1.0,
             motions=[(1, [-3.5, 2.0], [4.5, 8.0])]),
        dict(name="wide_sigma_subcell_motion", grid=[8, 8], sigma=2.0,
             motions=[(2, [3.3, 3.6], [3.7, 4.1])]),
        dict(name="several_joints", grid=[9, 8], sigma=1.0,
             motions=[(0, [1.1, 1.2], [4.3, 2.1]), (5, [7.2, 6.1], [2.3, 5.4]),
                      (6, [4.0, 0.0], [4.0, 7.0])]),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = pathlib.Path(__file__).resolve().parent.parent
    ap.add_argument("--out", default=str(root / "tests/data/tff_render_vectors.json"))
    ap.add_argument("--random", type=int, default=12)
    args = ap.parse_args()
    rng = np.random.default_rng(20180906)
    cases = edge_cases() + [random_case(rng, i) for i in range(args.random)]
    for c in cases:
        w, h = c["grid"]
        field = render_tff([(j, tuple(f), tuple(t)) for j, f, t in c["motions"]], NUM_JOINTS,
                           (h, w), c["sigma"])
        c["motions"] = [dict(joint=j, **{"from": f, "to": t}) for j, f, t in c["motions"]]
        # Channel-major, row-major flattening of [2*J, H, W]; float32 values printed exactly.
        c["field"] = [float(x) for x in field.ravel()]
    doc = dict(
        description="TFF ground-truth renderings (JointFlow paper Eq. 2-4) from "
                    "training/jointflow_train/tff_render.py; field is [2*num_joints, H, W] flattened "
                    "channel-major then row-major; channel 2j = x, 2j+1 = y; grid = [W, H]; "
                    "coordinates in grid cells (x = column, y = row).",
        generator="training/make_tff_vectors.py", num_joints=NUM_JOINTS, tolerance=1e-6, cases=cases)
    pathlib.Path(args.out).write_text(json.dumps(doc, separators=(",", ":")) + "\n")
    print(f"wrote {len(cases)} cases to {args.out}")


if __name__ == "__main__":
    main()
