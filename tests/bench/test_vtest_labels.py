#!/usr/bin/env python3
"""Checks the vtest.avi identity labels (tests/data/vtest-identity) and that jointflow-eval reads
them: boxes inside the frame, one box per id and frame, visits that are unbroken spans each of
one person (the persons file the same boxes under the person's id), visits.txt agreeing, and the
labels scored against themselves at 100. Every failed check is printed; exit 1 if any.
   test_vtest_labels.py JOINTFLOW_EVAL SOURCE_ROOT"""
import json
import os
import subprocess
import sys

evaluator, root = sys.argv[1], sys.argv[2]
labels = os.path.join(root, "tests", "data", "vtest-identity")
errors = []


def check(ok, message):
    if not ok:
        errors.append(message)


def seqinfo(name):
    with open(os.path.join(labels, name, "seqinfo.ini")) as f:
        return dict(line.strip().split("=", 1) for line in f if "=" in line)


def rows(name):
    """[(frame, id, x, y, w, h)] of a gt.txt, checking the MOTChallenge ground-truth columns."""
    out = []
    with open(os.path.join(labels, name, "gt", "gt.txt")) as f:
        for n, line in enumerate(f, 1):
            v = line.strip().split(",")
            check(len(v) == 9 and v[6:] == ["1", "1", "1.0"],
                  "%s gt.txt:%d: want 9 columns ending 1,1,1.0: %s" % (name, n, line.strip()))
            out.append((int(v[0]), int(v[1])) + tuple(float(x) for x in v[2:6]))
    return out


info = seqinfo("visits")
W, H, N = int(info["imWidth"]), int(info["imHeight"]), int(info["seqLength"])
check((W, H, N, info["frameRate"]) == (768, 576, 795, "10"),
      "visits/seqinfo.ini: vtest.avi is 768x576, 795 frames at 10 frames/s: %s" % info)
check(seqinfo("persons") == dict(info, name="vtest-persons"),
      "persons/seqinfo.ini differs from visits/seqinfo.ini but for its name")
visits, persons = rows("visits"), rows("persons")

seen = set()
span = {}
for f, i, x, y, w, h in visits:
    check(1 <= f <= N, "visit %d: frame %d outside 1-%d" % (i, f, N))
    check(w > 1 and h > 1 and x >= 0 and y >= 0 and x + w <= W + 0.05 and y + h <= H + 0.05,
          "visit %d frame %d: box %s not inside the %dx%d frame" % (i, f, (x, y, w, h), W, H))
    check((f, i) not in seen, "visit %d twice in frame %d" % (i, f))
    seen.add((f, i))
    span.setdefault(i, []).append(f)
for i, frames in span.items():
    check(sorted(frames) == list(range(min(frames), max(frames) + 1)),
          "visit %d is not an unbroken span of frames" % i)

with open(os.path.join(labels, "visits.txt")) as f:
    table = [[int(x) for x in line.split(",")] for line in f if not line.startswith("#")]
person_of = {v: p for v, p, *_ in table}
check(sorted(person_of) == sorted(span), "visits.txt lists other visits than gt.txt")
for v, p, first, last, n, tracker, key, interpolated in table:
    frames = span.get(v, [0])
    check((first, last, n) == (min(frames), max(frames), len(frames)),
          "visits.txt: visit %d is frames %d-%d (%d boxes) in gt.txt" %
          (v, min(frames), max(frames), len(frames)))
    check(tracker + key + interpolated == n, "visits.txt: visit %d's sources do not add up" % v)

# The persons file: the same rows with each visit's id replaced by its person's.
check(len(persons) == len(visits), "persons and visits gt.txt differ in length")
for a, b in zip(visits, persons):
    if a[1] not in person_of or a[0] != b[0] or a[2:] != b[2:] or b[1] != person_of[a[1]]:
        check(False, "persons gt.txt row %s is not visits row %s under person %s" %
              (b, a, person_of.get(a[1])))
        break
# A person is in one place at a time: their visits do not overlap.
by_person = {}
for v, p in person_of.items():
    by_person.setdefault(p, []).append((min(span[v]), max(span[v])))
for p, spans in by_person.items():
    spans.sort()
    for (a1, a2), (b1, b2) in zip(spans, spans[1:]):
        check(a2 < b1, "person %d: visits %d-%d and %d-%d overlap" % (p, a1, a2, b1, b2))

# jointflow-eval reads the labels: scored against themselves, everything is 100.
for name in ("visits", "persons"):
    folder = os.path.join(labels, name)
    run = subprocess.run([evaluator, "--mot-gt", folder, "--pred",
                          os.path.join(folder, "gt", "gt.txt"), "--json"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        check(False, "jointflow-eval --mot-gt %s failed: %s" % (folder, run.stderr.strip()))
        continue
    r = json.loads(run.stdout)["combined"]
    ids = len(set(p for _, p, *_ in persons)) if name == "persons" else len(span)
    check((r["frames"], r["gt_dets"], r["gt_ids"]) == (N, len(visits), ids),
          "%s: jointflow-eval read %d frames, %d boxes, %d ids; want %d, %d, %d" %
          (name, r["frames"], r["gt_dets"], r["gt_ids"], N, len(visits), ids))
    for key in ("idf1", "hota", "mota", "recall", "precision"):
        check(abs(r[key] - 100) < 1e-6, "%s against itself: %s %s, want 100" % (name, key, r[key]))
    check(r["id_switches"] == 0, "%s against itself: %d id switches" % (name, r["id_switches"]))

for e in errors:
    print("FAIL:", e)
print("%d visits of %d people, %d boxes: %s" % (len(span), len(by_person), len(visits),
                                              "%d checks failed" % len(errors) if errors else "ok"))
sys.exit(1 if errors else 0)
