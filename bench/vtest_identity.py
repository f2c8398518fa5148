#!/usr/bin/env python3
"""Our own labelled identity check on vtest.avi (issue 42, item 3): jointflow-track with every
similarity, re-entry on (default) and off (--reentry-time 0), scored by jointflow-eval --mot-gt
against tests/data/vtest-identity (ids = visits, then ids = persons), plus the predicted ids that
cover two labelled people for more than 10 frames. Writes docs/identity-vtest.md and .json.
   bench/vtest_identity.py [BUILD] [--video PATH] [--similarities auto,tff,...] [--out-dir docs]"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "bench", "vtest_labels"))
from motfile import match_frame, read_mot  # noqa: E402

LABELS = os.path.join(ROOT, "tests", "data", "vtest-identity")
SIMILARITIES = ["auto", "tff", "oks", "iou", "pckh", "flow"]
# The targets of issue 42 for this check.
TARGETS = {"idsw": 12, "hota": 63.0, "idf1_visits": 85.0, "idf1_persons": 90.0, "two_people": 0}
TWO_PEOPLE_FRAMES = 10


def evaluate(evaluator, gt, pred):
    out = subprocess.run([evaluator, "--mot-gt", gt, "--pred", pred, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["combined"]


def identity_counts(gt_persons, pred):
    """Per person: the predicted ids matched to them (IoU >= 0.5, greedy per frame). Per
    predicted id: the frames matched to each person; ids with more than TWO_PEOPLE_FRAMES frames
    on two or more people cover two people."""
    per_id = {}
    for f, gt in gt_persons.items():
        for person, pid in match_frame(gt, pred.get(f, {})).items():
            per_id.setdefault(pid, {}).setdefault(person, 0)
            per_id[pid][person] += 1
    ids_per_person = {}
    for pid, persons in per_id.items():
        for person in persons:
            ids_per_person.setdefault(person, set()).add(pid)
    two = {pid: persons for pid, persons in per_id.items()
           if sum(n > TWO_PEOPLE_FRAMES for n in persons.values()) >= 2}
    return ({p: len(ids) for p, ids in sorted(ids_per_person.items())},
            {str(pid): {str(p): n for p, n in sorted(persons.items())}
             for pid, persons in sorted(two.items())})


def load_average():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def main():
    a = argparse.ArgumentParser()
    a.add_argument("build", nargs="?", default="build")
    a.add_argument("--video", default=os.environ.get(
        "JOINTFLOW_VTEST", "/usr/share/doc/opencv-doc/examples/data/vtest.avi"))
    a.add_argument("--similarities", default=",".join(SIMILARITIES))
    a.add_argument("--backend", default="openvino")
    a.add_argument("--out-dir", default=os.path.join(ROOT, "docs"))
    a.add_argument("--markdown-only", action="store_true",
                   help="rewrite identity-vtest.md from identity-vtest.json without running")
    args = a.parse_args()
    if args.markdown_only:
        with open(os.path.join(args.out_dir, "identity-vtest.json")) as f:
            out = json.load(f)
        with open(os.path.join(args.out_dir, "identity-vtest.md"), "w") as f:
            f.write(markdown(out))
        return
    track = os.path.join(args.build, "apps", "jointflow-track")
    evaluator = os.path.join(args.build, "apps", "jointflow-eval")
    gt_persons = read_mot(os.path.join(LABELS, "persons", "gt", "gt.txt"))
    started, load0 = time.time(), load_average()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for similarity in args.similarities.split(","):
            for reentry in (True, False):
                pred = os.path.join(tmp, "%s-%d.txt" % (similarity, reentry))
                cmd = [track, args.video, "-q", "--backend", args.backend, "--similarity",
                       similarity, "--output-mot", pred]
                if not reentry:
                    cmd += ["--reentry-time", "0"]
                t0 = time.time()
                subprocess.run(cmd, check=True)
                seconds = time.time() - t0
                visits = evaluate(evaluator, os.path.join(LABELS, "visits"), pred)
                persons = evaluate(evaluator, os.path.join(LABELS, "persons"), pred)
                ids_per_person, two = identity_counts(gt_persons, read_mot(pred))
                rows.append({"similarity": similarity, "reentry": reentry,
                             "command": " ".join(cmd[1:]).replace(pred, "PRED.txt"),
                             "tracker_seconds": round(seconds, 1), "visits": visits,
                             "persons": persons, "ids_per_person": ids_per_person,
                             "ids_covering_two_people": two})
                print("%-5s reentry %-3s  visits IDF1 %.1f HOTA %.1f IDSW %d  persons IDF1 %.1f"
                      "  two-people ids %d" % (similarity, "on" if reentry else "off",
                                               visits["idf1"], visits["hota"],
                                               visits["id_switches"], persons["idf1"], len(two)),
                      file=sys.stderr)
    minutes, load1 = (time.time() - started) / 60, load_average()
    counts = open(os.path.join(LABELS, "visits.txt")).read().splitlines()[1:]
    people = len({line.split(",")[1] for line in counts})
    out = {"labels": "tests/data/vtest-identity", "video": os.path.basename(args.video),
           "backend": args.backend, "people": people, "visits": len(counts),
           "targets": TARGETS, "minutes": round(minutes, 1), "load_start": load0,
           "load_end": load1, "runs": rows}
    write_report(args.out_dir, "identity-vtest", out, markdown)


def write_report(out_dir, stem, out, to_markdown):
    """OUT_DIR/STEM.json (the raw figures) and STEM.md (to_markdown of them)."""
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, stem + ".json"), "w") as f:
        json.dump(out, f, indent=1)
    with open(os.path.join(out_dir, stem + ".md"), "w") as f:
        f.write(to_markdown(out))


def markdown(out):
    t = out["targets"]
    ok = lambda good: "" if good else " ✗"
    lines = [
        "# Identity on vtest.avi against our own labels",
        "",
        "Written by `bench/vtest_identity.py` (`make bench-identity-vtest`; also run by `make "
        "bench-identity` and `make bench`); the raw figures are in `identity-vtest.json`. The "
        "labels: [tests/data/vtest-identity](../tests/data/vtest-identity/README.md), %d people "
        "in %d visits, boxes and identities checked by eye (how, and what is weak, in its "
        "README). jointflow-track with `--backend %s` and its defaults but the similarity; "
        "re-entry on is the default (`--reentry-time 30`), off is `--reentry-time 0`. Took %.1f "
        "min on this machine (2 cores; 1-minute load average %.1f at the start, %.1f at the "
        "end)." % (out["people"], out["visits"], out["backend"], out["minutes"],
                   out["load_start"], out["load_end"]),
        "",
        "Per visit: the labels' ids are visits (a person who leaves and comes back is a new "
        "id), scored by `jointflow-eval --mot-gt tests/data/vtest-identity/visits`. Per person: "
        "the same boxes with one id per person (`.../persons`), which only a tracker that "
        "recognises people coming back can score well on. Ids on two people: predicted ids "
        "matched (IoU >= 0.5, greedy per frame) to two or more labelled people for more than "
        "%d frames each. The targets of issue 42 (per visit: ID switches <= %d, HOTA >= %g, "
        "IDF1 >= %g; per person IDF1 >= %g; no id on two people): a miss is marked ✗."
        % (TWO_PEOPLE_FRAMES, t["idsw"], t["hota"], t["idf1_visits"], t["idf1_persons"]),
        "",
        "| similarity | re-entry | visits: IDF1 | HOTA | AssA | ID switches | MOTA | recall "
        "| persons: IDF1 | HOTA | ids per person (mean / max) | ids on two people |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in out["runs"]:
        v, p = r["visits"], r["persons"]
        n = list(r["ids_per_person"].values())
        lines.append(
            "| %s | %s | %.1f%s | %.1f%s | %.1f | %d%s | %.1f | %.1f | %.1f%s | %.1f | %.2f / %d "
            "| %d%s |" % (
                r["similarity"], "on" if r["reentry"] else "off", v["idf1"],
                ok(v["idf1"] >= t["idf1_visits"]), v["hota"], ok(v["hota"] >= t["hota"]),
                v["assa"], v["id_switches"], ok(v["id_switches"] <= t["idsw"]), v["mota"],
                v["recall"], p["idf1"], ok(p["idf1"] >= t["idf1_persons"]), p["hota"],
                sum(n) / max(len(n), 1), max(n or [0]), len(r["ids_covering_two_people"]),
                ok(not r["ids_covering_two_people"])))
    lines += [
        "",
        "The boxes of the labels started from jointflow-track's own boxes (default settings, "
        "OpenVINO) and were corrected where wrong, so detection figures (recall, MOTA, DetA "
        "inside HOTA: DetA %.1f-%.1f per visit here) favour this detector, and HOTA (about "
        "sqrt(DetA x AssA)) passes its target on DetA; the identity figures (IDF1, AssA, ID switches, ids "
        "per person, ids on two people) are what this check is for." % (
            min(r["visits"]["deta"] for r in out["runs"]),
            max(r["visits"]["deta"] for r in out["runs"])),
        "",
        "ByteTrack and Norfair re-tracking the same poses, scored against the same labels: "
        "[peer-trackers.md](peer-trackers.md) (`make bench-peers`).",
        "",
        "OpenVINO's default precision is bf16 on CPUs with AVX-512 BF16 or AMX (the one of these runs) and f32 elsewhere, and the ids on this clip follow such small differences: with `--precision f32` (8 December, with tiles on by default) auto scores per visit 4 id switches and IDF1 90.8, per person IDF1 96.2, against 3, 90.8 and 96.4 in bf16 (2, 91.0 and 96.3 on 7 December, before the tile merge dropped cut poses no other run saw; the whole frame only, `--tiles false`, the default before: 21, 88.9, 92.3 in f32 and 20, 90.1, 95.0 in bf16). The `vtest-identity` test (tests/bench, suite slow) checks floors on the f32 figures, which every CPU gives.",
        "",
        "Ids on two people, per run (predicted id: {person: frames}):",
        "",
    ]
    for r in out["runs"]:
        two = r["ids_covering_two_people"]
        lines.append("- %s, re-entry %s: %s" % (
            r["similarity"], "on" if r["reentry"] else "off",
            "; ".join("id %s %s" % (i, json.dumps(ps)) for i, ps in two.items()) or "none"))
    lines += ["", "The command of each run (PRED.txt: the MOT file it writes):", ""]
    lines += ["    jointflow-track " + r["command"] for r in out["runs"][:2]]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
