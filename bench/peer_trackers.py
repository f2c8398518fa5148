#!/usr/bin/env python3
"""jointflow against two peer trackers on the same poses, scored against our own labels of
vtest.avi (issue 42): jointflow-track with its defaults writes its poses; ByteTrack (roboflow
`trackers` 2.6.1) and Norfair 2.3 re-track them (bench/peer_track.py, each in its pinned venv
from bench/peer_venv.sh), as the issue's table did against the held-out ground truth. Writes
docs/peer-trackers.md, .json and .png (bench/plot_peers.py).
   bench/peer_trackers.py [BUILD] [--video PATH] [--out-dir docs]"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "vtest_labels"))
from motfile import match_frame, read_mot  # noqa: E402
from vtest_identity import (LABELS, TARGETS, evaluate, identity_counts,  # noqa: E402
                            load_average, write_report)

# Each peer: (name in the table, venv, arguments of peer_track.py). ByteTrack at the issue's
# thresholds (0.3) and one lower; Norfair's keypoint reach at three fractions of the frame's
# height, since the people of vtest.avi (40-120 px tall) are smaller than its demo's: the peers
# get their best setting in the table, not one we picked against them.
PEERS = [
    ("ByteTrack, score thresholds 0.3", "bytetrack", ["bytetrack", "--threshold", "0.3"]),
    ("ByteTrack, score thresholds 0.2", "bytetrack", ["bytetrack", "--threshold", "0.2"]),
    ("Norfair keypoints, reach 1/60 of the height", "norfair", ["norfair", "--reach", "60"]),
    ("Norfair keypoints, reach 1/40 of the height", "norfair", ["norfair", "--reach", "40"]),
    ("Norfair keypoints, reach 1/25 of the height", "norfair", ["norfair", "--reach", "25"]),
]


# vtest.avi's frames 1-140: three men cross and stand at the sign, one pose often covering two of
# them (docs/tracking.md, step 5), where the trackers differ most.
SIGN_LAST_FRAME = 140


def id_changes(gt_visits, pred):
    """Changes of the predicted id matched to a labelled visit (greedy IoU >= 0.5 per frame), at
    the sign (frames <= SIGN_LAST_FRAME) and after it. Every change counts, so these exceed
    CLEAR MOT's ID switches, which keep a match while its IoU stays >= 0.5."""
    last, frames = {}, []
    for f in sorted(gt_visits):
        for visit, pid in match_frame(gt_visits[f], pred.get(f, {})).items():
            if last.get(visit, pid) != pid:
                frames.append(f)
            last[visit] = pid
    sign = sum(f <= SIGN_LAST_FRAME for f in frames)
    return {"sign": sign, "after": len(frames) - sign, "frames": frames}


def score(evaluator, gt_persons, gt_visits, pred):
    boxes = read_mot(pred)
    ids_per_person, two = identity_counts(gt_persons, boxes)
    return {"visits": evaluate(evaluator, os.path.join(LABELS, "visits"), pred),
            "persons": evaluate(evaluator, os.path.join(LABELS, "persons"), pred),
            "distinct_ids": len({i for row in boxes.values() for i in row}),
            "id_changes": id_changes(gt_visits, boxes),
            "ids_per_person": ids_per_person, "ids_covering_two_people": two}


def main():
    a = argparse.ArgumentParser()
    a.add_argument("build", nargs="?", default="build")
    a.add_argument("--video", default=os.environ.get(
        "JOINTFLOW_VTEST", "/usr/share/doc/opencv-doc/examples/data/vtest.avi"))
    a.add_argument("--backend", default="openvino")
    a.add_argument("--out-dir", default=os.path.join(ROOT, "docs"))
    args = a.parse_args()
    track = os.path.join(args.build, "apps", "jointflow-track")
    evaluator = os.path.join(args.build, "apps", "jointflow-eval")
    gt_persons = read_mot(os.path.join(LABELS, "persons", "gt", "gt.txt"))
    gt_visits = read_mot(os.path.join(LABELS, "visits", "gt", "gt.txt"))
    started, load0 = time.time(), load_average()
    pythons = {}
    for venv in sorted({p[1] for p in PEERS}):
        pythons[venv] = subprocess.run(["bash", os.path.join(HERE, "peer_venv.sh"), args.build,
                                        venv], check=True, capture_output=True,
                                       text=True).stdout.strip()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        poses = os.path.join(tmp, "poses.jsonl")
        for name, extra in (("jointflow, defaults (re-entry on)", []),
                            ("jointflow, --reentry-time 0", ["--reentry-time", "0"])):
            pred = os.path.join(tmp, "jointflow-%d.txt" % len(rows))
            cmd = [track, args.video, "-q", "--backend", args.backend, "--output-mot", pred]
            # The peers re-track the poses of the default run, as in the issue.
            cmd += extra or ["--output-json", poses]
            print("==", name, file=sys.stderr)
            subprocess.run(cmd, check=True)
            rows.append(dict(tracker=name, **score(evaluator, gt_persons, gt_visits, pred)))
        for name, venv, peer_args in PEERS:
            pred = os.path.join(tmp, "peer-%d.txt" % len(rows))
            print("==", name, file=sys.stderr)
            subprocess.run([pythons[venv], os.path.join(HERE, "peer_track.py"), peer_args[0],
                            poses, pred] + peer_args[1:], check=True)
            rows.append(dict(tracker=name, **score(evaluator, gt_persons, gt_visits, pred)))
    out = {"labels": "tests/data/vtest-identity", "video": os.path.basename(args.video),
           "backend": args.backend, "targets": TARGETS,
           "minutes": round((time.time() - started) / 60, 1), "load_start": load0,
           "load_end": load_average(), "runs": rows}
    write_report(args.out_dir, "peer-trackers", out, markdown)
    # The picture: where in the clip each tracker changes ids (matplotlib from the bench venv).
    python = subprocess.run(["bash", os.path.join(HERE, "venv.sh"), args.build], check=True,
                            capture_output=True, text=True).stdout.strip()
    subprocess.run([python, os.path.join(HERE, "plot_peers.py"),
                    os.path.join(args.out_dir, "peer-trackers.json"),
                    os.path.join(args.out_dir, "peer-trackers.png"), str(SIGN_LAST_FRAME)],
                   check=True)


def markdown(out):
    lines = [
        "# jointflow and two peer trackers on the same poses (vtest.avi, our labels)",
        "",
        "Written by `bench/peer_trackers.py` (`make bench-peers`); the raw figures are in "
        "`peer-trackers.json`. jointflow-track (`--backend %s`, its defaults) tracks vtest.avi "
        "and writes its poses; ByteTrack (roboflow `trackers` 2.6.1, Apache-2.0) re-tracks their "
        "boxes and person scores, Norfair 2.3 (BSD-3-Clause) their 17 keypoints, each from a "
        "pinned venv (bench/peers/). So every row has the same detections, as in issue 42's "
        "table, which scored the same trackers against ground truth held out from us. Scored "
        "by `jointflow-eval --mot-gt` against [our labels](../tests/data/vtest-identity/README.md)"
        ": per visit (a person who leaves and comes back is a new id) and per person (one id "
        "per person). Took %.1f min (2 cores; 1-minute load average %.1f at the start, %.1f "
        "at the end)." % (out["backend"], out["minutes"], out["load_start"], out["load_end"]),
        "",
        "| tracker | visits: IDF1 | HOTA | AssA | ID switches | id changes: at the sign "
        "| after it | MOTA | recall | persons: IDF1 | distinct ids | ids on two people |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in out["runs"]:
        v, p, c = r["visits"], r["persons"], r["id_changes"]
        lines.append("| %s | %.1f | %.1f | %.1f | %d | %d | %d | %.1f | %.1f | %.1f | %d | %d |" % (
            r["tracker"], v["idf1"], v["hota"], v["assa"], v["id_switches"], c["sign"],
            c["after"], v["mota"], v["recall"], p["idf1"], r["distinct_ids"],
            len(r["ids_covering_two_people"])))
    lines += [
        "",
        "How the peers are set: ByteTrack's two score thresholds (a new track; the first "
        "matching pass) at 0.3 as in the issue, and at 0.2, since MoveNet's person scores on "
        "vtest.avi lie at 0.15-0.6, under the 0.7 and 0.6 it assumes; its frame rate from the "
        "video's timestamps (10 frames/s). Norfair matches by its keypoint vote with the values "
        "of its OpenPose demo (keypoints from score 0.2, a match below distance 0.3); a keypoint "
        "matches within a fraction of the frame's height, tried at three fractions because the "
        "people here are 40-120 px tall. Both report a track only once it has been matched on "
        "a few frames, and ByteTrack starts none from a pose under its threshold: they report "
        "fewer poses (recall), which is also where a tracker can swap ids.",
        "",
        "Id changes: every change of the predicted id matched to a labelled visit (IoU >= 0.5, "
        "greedy per frame), split at frame %d: frames 1-%d are vtest.avi's sign, where three "
        "men cross and stand; with the whole frame only (`--tiles false`, the default before "
        "7 December 2026) one pose often covered two of them (docs/tracking.md, step 5). "
        "They count more than the ID switches, which keep a match while its IoU stays >= 0.5."
        % (SIGN_LAST_FRAME, SIGN_LAST_FRAME),
        "",
        "![Id changes along the clip, one row per tracker](peer-trackers.png)",
        "",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
