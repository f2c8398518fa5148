"""Builds the vtest.avi identity labels from the tracker's starting boxes and the hand-written
edits (edits.txt), deterministically: tests/data/vtest-identity/{visits,persons}/gt/gt.txt.

edits.txt, one command a line (# comments):
  person P NAME...          a person and how they look
  visit V P                 visit V (one continuous stay in view) is person P's
  take V SRC ID F1 F2       the boxes of tracker id ID in frames F1..F2 go to V; SRC d is
                            start/default.txt, n start/native.txt
  key V F X Y W H           a box drawn by hand for V at frame F (replaces any box there)
  drop V F1 F2              V has no box in F1..F2 taken from the tracker (keys stay)
  span V F1 F2              V is in view exactly in F1..F2: boxes outside are removed; missing
                            frames inside are interpolated linearly between the nearest boxes
Later commands win. Every visit's frames between its first and last box are filled by linear
interpolation (people hidden behind the sign or another person, or missed by the detector)."""
import os
import sys
from collections import defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
OUT = os.path.join(ROOT, "tests", "data", "vtest-identity")
W, H, N = 768, 576, 795


def read_start(name):
    out = defaultdict(dict)
    for line in open(os.path.join(HERE, "start", name + ".txt")):
        f, i, x, y, w, h = line.strip().split(",")
        out[int(i)][int(f)] = tuple(float(v) for v in (x, y, w, h))
    return out


def clip(b):
    x, y, w, h = b
    x0, y0 = max(0.0, x), max(0.0, y)
    x1, y1 = min(float(W), x + w), min(float(H), y + h)
    return (x0, y0, x1 - x0, y1 - y0)


def main():
    edits = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "edits.txt")
    starts = {}
    persons, visit_person = {}, {}
    boxes = defaultdict(dict)   # visit -> frame -> box
    source = defaultdict(dict)  # visit -> frame -> "tracker" | "key" | "interpolated"
    spans = {}
    used = {}                   # (src, id, frame) -> visit: a tracker box goes to one visit only
    for n, line in enumerate(open(edits), 1):
        words = line.split("#")[0].split()
        if not words:
            continue
        where = "%s:%d" % (edits, n)
        cmd, a = words[0], words[1:]
        if cmd == "person":
            persons[int(a[0])] = " ".join(a[1:])
        elif cmd == "visit":
            visit_person[int(a[0])] = int(a[1])
        elif cmd == "take":
            v, src, tid, f1, f2 = int(a[0]), a[1], int(a[2]), int(a[3]), int(a[4])
            if src not in starts:
                starts[src] = read_start({"d": "default", "n": "native"}[src])
            for f, b in starts[src][tid].items():
                if f1 <= f <= f2:
                    if (src, tid, f) in used and used[(src, tid, f)] != v:
                        sys.exit("%s: %s id %d frame %d already went to visit %d" %
                                 (where, src, tid, f, used[(src, tid, f)]))
                    used[(src, tid, f)] = v
                    boxes[v][f] = b
                    source[v][f] = "tracker"
        elif cmd == "key":
            v, f = int(a[0]), int(a[1])
            boxes[v][f] = tuple(float(x) for x in a[2:6])
            source[v][f] = "key"
        elif cmd == "drop":
            v, f1, f2 = int(a[0]), int(a[1]), int(a[2])
            for f in list(boxes[v]):
                if f1 <= f <= f2 and source[v][f] == "tracker":
                    del boxes[v][f], source[v][f]
        elif cmd == "span":
            spans[int(a[0])] = (int(a[1]), int(a[2]))
        else:
            sys.exit("%s: unknown command %s" % (where, cmd))
    for v in boxes:
        if v not in visit_person:
            sys.exit("visit %d has no person (visit V P)" % v)
        f1, f2 = spans.get(v, (min(boxes[v]), max(boxes[v])))
        for f in list(boxes[v]):
            if not f1 <= f <= f2:
                del boxes[v][f], source[v][f]
        known = sorted(boxes[v])
        if not known or known[0] != f1 or known[-1] != f2:
            sys.exit("visit %d: span %d-%d needs a box at both ends (has %s-%s)" %
                     (v, f1, f2, known[0] if known else "-", known[-1] if known else "-"))
        for a, b in zip(known, known[1:]):
            for f in range(a + 1, b):
                t = (f - a) / (b - a)
                boxes[v][f] = tuple(p + t * (q - p) for p, q in zip(boxes[v][a], boxes[v][b]))
                source[v][f] = "interpolated"
    rows = sorted((f, v, clip(b)) for v in boxes for f, b in boxes[v].items())
    for name, ident in (("visits", lambda v: v), ("persons", lambda v: visit_person[v])):
        d = os.path.join(OUT, name)
        os.makedirs(os.path.join(d, "gt"), exist_ok=True)
        with open(os.path.join(d, "seqinfo.ini"), "w") as out:
            out.write("[Sequence]\nname=vtest-%s\nimDir=img1\nframeRate=10\nseqLength=%d\n"
                      "imWidth=%d\nimHeight=%d\nimExt=.jpg\n" % (name, N, W, H))
        with open(os.path.join(d, "gt", "gt.txt"), "w") as out:
            for f, v, (x, y, w, h) in rows:
                out.write("%d,%d,%.1f,%.1f,%.1f,%.1f,1,1,1.0\n" % (f, ident(v), x, y, w, h))
    with open(os.path.join(OUT, "visits.txt"), "w") as out:
        out.write("# visit,person,first_frame,last_frame,boxes,tracker,key,interpolated\n")
        for v in sorted(boxes):
            s = list(source[v].values())
            out.write("%d,%d,%d,%d,%d,%d,%d,%d\n" % (v, visit_person[v], min(boxes[v]),
                      max(boxes[v]), len(s), s.count("tracker"), s.count("key"),
                      s.count("interpolated")))
    with open(os.path.join(OUT, "interpolated.txt"), "w") as out:
        out.write("# visit,first_frame,last_frame: runs of interpolated boxes (hidden or missed)\n")
        for v in sorted(boxes):
            runs = []
            for f in sorted(f for f in boxes[v] if source[v][f] == "interpolated"):
                if runs and runs[-1][1] == f - 1:
                    runs[-1][1] = f
                else:
                    runs.append([f, f])
            for first, last in runs:
                out.write("%d,%d,%d\n" % (v, first, last))
    with open(os.path.join(OUT, "persons.txt"), "w") as out:
        out.write("# person,description\n")
        for p in sorted(persons):
            out.write("%d,%s\n" % (p, persons[p]))
    total = sum(len(b) for b in boxes.values())
    inter = sum(list(s.values()).count("interpolated") for s in source.values())
    keys = sum(list(s.values()).count("key") for s in source.values())
    print("%d persons, %d visits, %d boxes (%d interpolated, %d keyed by hand)" %
          (len(set(visit_person[v] for v in boxes)), len(boxes), total, inter, keys))


main()
