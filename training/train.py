#!/usr/bin/env python3
"""Trains the TFF network on cached pairs (precompute.py), exports it to ONNX, checks parity.

Loss: paper Eq. 5 (masked squared L2), by default with cells inside some Omega weighted 10x
(--positive-weight 1 is Eq. 5 as printed; why: training/README.md). Optimiser: Adam with a step
decay of gamma 0.333 like the paper's (paper: 40 epochs, decay after 7; here after 60 % of the
steps by default, since a run is ~1 epoch). The defaults are the settings of the shipped model.

Usage: training/.venv/bin/python training/train.py --cache training/.cache/maps --out training/runs/NAME
           [--steps 2000] [--width 24] [--grid-stride 2] [--val VIDEO_STEM ...]
Writes: OUT/tff.onnx, OUT/checkpoint.pt, OUT/log.csv, OUT/loss.png, OUT/summary.json.
"""
import argparse
import csv
import glob
import json
import os
import pathlib
import sys
import time

import numpy as np
import torch

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.dataset import PairDataset  # noqa: E402
from jointflow_train.export import export_onnx, parity  # noqa: E402
from jointflow_train.model import TFFNet, masked_l2_loss  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_VAL = ["yoloopencv_pedestrians", "mmaction2_test_video_structuralize", "violence_fight"]


def split_files(cache: str, val_stems):
    files = sorted(glob.glob(os.path.join(cache, "*.npz")))
    if not files:
        sys.exit(f"no cached videos in {cache}: run training/precompute.py first")
    val = [f for f in files if pathlib.Path(f).stem in val_stems]
    train = [f for f in files if f not in val]
    return train, val


def batch(ds, idxs, crop, rng):
    parts = [ds.crop(int(i), crop, rng) for i in idxs]
    return [torch.from_numpy(np.stack(p)) for p in zip(*parts)]


@torch.no_grad()
def zero_baseline(ds, idxs):
    """validate() of a network that outputs 0 everywhere: what the loss must beat to mean the
    network predicts motion rather than just the empty background."""
    total, cells = 0.0, 0.0
    for i in idxs:
        _, target, mask, _, _ = ds.example(int(i))
        total += float((mask * (target.reshape(mask.shape[0], 2, *mask.shape[1:]) ** 2).sum(1)).sum())
        cells += float(mask.sum())
    return total / max(cells, 1)


@torch.no_grad()
def validate(model, ds, idxs):
    """Mean masked squared error per unmasked cell and joint, over full grids."""
    model.eval()
    total, cells = 0.0, 0.0
    for i in idxs:
        x, target, mask, _, _ = ds.example(int(i))
        h, w = x.shape[1:]
        ph, pw = -h % 2, -w % 2  # grid_stride 2 needs even sizes (MoveNet grids always are)
        xt = torch.from_numpy(np.pad(x, ((0, 0), (0, ph), (0, pw))))[None]
        pred = model(xt)[..., :h, :w]
        total += float(masked_l2_loss(pred, torch.from_numpy(target)[None], torch.from_numpy(mask)[None]))
        cells += float(mask.sum())
    model.train()
    return total / max(cells, 1)


def plot(log_rows, path, zero_val=None, positive_weight=1.0):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = [r["step"] for r in log_rows]
    fig, ax = plt.subplots(figsize=(6, 3.5), dpi=100)
    ax.plot(steps, [r["train_loss_per_cell"] for r in log_rows], label="train (crops, running mean" + (
        f", cells in Omega x{positive_weight:g})" if positive_weight != 1 else ")"))
    vs = [(r["step"], r["val_loss_per_cell"]) for r in log_rows if r["val_loss_per_cell"] != ""]
    if vs:
        ax.plot(*zip(*vs), "o-", label="held-out videos (full grids, Eq. 5)")
    if zero_val is not None:
        ax.axhline(zero_val, color="grey", ls="--", label="held-out, all-zero output")
    ax.set_xlabel("step")
    ax.set_ylabel("masked squared L2 per cell and joint")
    ax.set_yscale("log")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title("TFF network training")
    fig.tight_layout()
    fig.savefig(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache", default=str(ROOT / "training/.cache/maps"))
    ap.add_argument("--out", default=str(ROOT / "training/runs/latest"))
    ap.add_argument("--val", nargs="*", default=DEFAULT_VAL, help="video stems held out for validation")
    ap.add_argument("--width", type=int, default=24)
    ap.add_argument("--grid-stride", type=int, default=2)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--crop", type=int, default=40)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--positive-weight", type=float, default=10.0,
                    help="loss weight of cells with a non-zero target (1 = paper Eq. 5)")
    ap.add_argument("--decay-every", type=float, default=0.6,
                    help="fraction of the steps after which the learning rate is multiplied by 0.333 "
                         "(paper: 7 of 40 epochs)")
    ap.add_argument("--strides", type=int, nargs="*", default=[1, 2, 3])
    ap.add_argument("--no-flips", action="store_true")
    ap.add_argument("--no-warps", action="store_true")
    ap.add_argument("--warp-share", type=float, default=0.5,
                    help="share of each batch drawn from the camera-motion pairs (they are ~7 %% of the "
                         "pairs but carry most of the motions longer than a grid cell)")
    ap.add_argument("--val-every", type=int, default=250)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    torch.manual_seed(args.seed)
    torch.set_num_threads(args.threads)
    rng = np.random.default_rng(args.seed)
    os.makedirs(args.out, exist_ok=True)
    train_files, val_files = split_files(args.cache, args.val)
    train = PairDataset(train_files, args.strides, not args.no_flips, not args.no_warps)
    val = PairDataset(val_files, args.strides, use_flips=False, use_warps=False) if val_files else None
    val_idx = np.random.default_rng(1).choice(len(val), min(60, len(val)), replace=False) if val else []
    warp_idx = np.array([i for i, e in enumerate(train.entries) if e[0] == "warp"])
    pair_idx = np.array([i for i, e in enumerate(train.entries) if e[0] == "pair"])
    warp_share = args.warp_share if len(warp_idx) else 0.0

    def draw(n):
        k = int(rng.binomial(n, warp_share))
        return np.concatenate([rng.choice(warp_idx, k), rng.choice(pair_idx, n - k)]) if k else rng.choice(pair_idx, n)

    print(f"train: {len(train_files)} videos, {len(train)} pairs ({len(warp_idx)} camera-motion); held out: "
          f"{[pathlib.Path(f).stem for f in val_files]}, {len(val_idx)} pairs checked", flush=True)

    model = TFFNet(width=args.width, grid_stride=args.grid_stride)
    sample = np.concatenate([train.example(int(i))[0].reshape(2 * (model.feature_channels + 17), -1)
                             for i in rng.choice(len(train), 64, replace=False)], 1)
    model.set_input_stats(torch.from_numpy(sample.mean(1)), torch.from_numpy(sample.std(1)))
    opt = torch.optim.Adam([p for p in model.parameters() if p.requires_grad], lr=args.lr)
    sched = torch.optim.lr_scheduler.StepLR(opt, step_size=max(1, round(args.steps * args.decay_every)), gamma=0.333)
    rows, running, t0 = [], None, time.time()
    with open(os.path.join(args.out, "log.csv"), "w", newline="") as logf:
        writer = csv.DictWriter(logf, ["step", "seconds", "lr", "train_loss_per_cell", "val_loss_per_cell"])
        writer.writeheader()
        for step in range(1, args.steps + 1):
            x, target, mask = batch(train, draw(args.batch), args.crop, rng)
            loss = masked_l2_loss(model(x), target, mask, args.positive_weight)
            opt.zero_grad()
            loss.backward()
            opt.step()
            sched.step()
            per_cell = float(loss) * args.batch / max(float(mask.sum()), 1)
            running = per_cell if running is None else 0.98 * running + 0.02 * per_cell
            if step % 50 == 0 or step == args.steps:
                v = validate(model, val, val_idx) if val and (step % args.val_every == 0 or step == args.steps) else ""
                row = dict(step=step, seconds=round(time.time() - t0, 1), lr=opt.param_groups[0]["lr"],
                           train_loss_per_cell=running, val_loss_per_cell=v)
                if v != "":  # a snapshot per validation, for a look while the run goes on
                    torch.save(dict(config=model.config(), state=model.state_dict(), args=vars(args), step=step),
                               os.path.join(args.out, "checkpoint.pt"))
                writer.writerow(row)
                logf.flush()
                rows.append(row)
                eta = (time.time() - t0) / step * (args.steps - step)
                print(f"step {step}/{args.steps}  loss/cell {running:.5f}  val {v if v == '' else f'{v:.5f}'}  "
                      f"lr {row['lr']:.2e}  {row['seconds']:.0f} s, eta {eta:.0f} s", flush=True)

    train_seconds = time.time() - t0
    torch.save(dict(config=model.config(), state=model.state_dict(), args=vars(args)),
                os.path.join(args.out, "checkpoint.pt"))
    zero_val = zero_baseline(val, val_idx) if val else None
    plot(rows, os.path.join(args.out, "loss.png"), zero_val, args.positive_weight)
    onnx_path = os.path.join(args.out, "tff.onnx")
    export_onnx(model, onnx_path, dict(spatial_model="movenet_multipose", grid="MoveNet stride-4 grid",
                                       sigma=1.0, steps=args.steps, train_videos=len(train_files)))
    par = parity(model, onnx_path)
    summary = dict(args=vars(args), train_pairs=len(train), train_seconds=round(train_seconds),
                   final_train_loss_per_cell=running, final_val_loss_per_cell=rows[-1]["val_loss_per_cell"],
                   val_loss_per_cell_all_zero_output=zero_val,
                   parity_max_abs=par, torch_threads=torch.get_num_threads())
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
