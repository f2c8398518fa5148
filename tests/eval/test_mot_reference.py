"""Cross-check of jointflow-eval's MOTChallenge box figures against py-motmetrics 1.4.0 and TrackEval.

Synthetic MOT17-style sequences (random walks; ground truth with distractor classes, other classes,
flag-0 rows, low-visibility rows, frames without people) and predictions made from them (jitter that
brings the IoU near or below 0.5, dropped boxes, false boxes, id swaps, new ids, empty frames,
boxes on distractors, rows with id -1, rows past the last frame, 7-, 8- and 10-column files and one
JSON Lines file) are written into a MOTChallenge layout and scored by jointflow-eval --json. The
references, computed independently of the C++ code:
- TrackEval (trackeval.Evaluator + MotChallenge2DBox, metrics HOTA, CLEAR, Identity) on copies of
  the files that spell out what the tool's options mean: frames past the sequence's length and
  predictions under --min-score left out, ids -1 made distinct, and for --min-visibility V > 0
  each pedestrian row with flag != 0 and visibility < V relabelled class 8 (a distractor);
- py-motmetrics' MOTAccumulator fed per frame with TrackEval's preprocessed ids and 1 - IoU
  distances, pairs with IoU < 0.5 forbidden.
CLEAR MOT and identity figures must equal motmetrics', HOTA and its parts TrackEval's, per sequence
and combined (motmetrics' OVERALL row, TrackEval's COMBINED_SEQ), counts exactly and percentages to
1e-6. TrackEval's own CLEAR and Identity results are printed beside motmetrics'; where the two
references disagree, the first frame whose matches differ is found and its cause named (the known
ones: motmetrics re-links a track to its last matched hypothesis after a gap, TrackEval's
continuation bonus only spans the previous evaluated frame; TrackEval maximises summed IoU where
motmetrics first maximises the number of matches; equal-cost ties). An unexplained disagreement
is a failure.

usage: test_mot_reference.py JOINTFLOW_EVAL [DATA_DIR]
Runs on synthetic sequences always, and on the 7 sequences of DATA_DIR/mot17-mini/train (their own
det/det.txt as predictions, --min-score 0.5) when DATA_DIR holds them. Exits 77 (skipped) when
jointflow-eval has no --mot-gt or the MOT17 data is absent.
"""
import contextlib
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import motmetrics as mm
import numpy as np

with contextlib.redirect_stdout(io.StringIO()):
    import trackeval  # its datasets/__init__ prints a note when pycocotools (masks only) is absent

DISTRACTOR_CLASSES = (2, 7, 8, 12)  # person_on_vehicle, static_person, distractor, reflection
OTHER_CLASSES = (3, 4, 5, 6, 9, 10, 11, 13)  # neither pedestrian nor distractor
HOTA_KEYS = {"hota": "HOTA", "deta": "DetA", "assa": "AssA", "loca": "LocA", "detre": "DetRe",
             "detpr": "DetPr", "assre": "AssRe", "asspr": "AssPr"}
COUNT_KEYS = ("frames", "gt_dets", "pred_dets", "gt_ids", "pred_ids", "id_switches", "matches",
              "false_positives", "misses", "idtp", "idfp", "idfn")
PERCENT_KEYS = ("recall", "precision", "mota", "motp", "idf1", "idp", "idr") + tuple(HOTA_KEYS)
MM_METRICS = ["num_frames", "num_objects", "num_predictions", "num_detections", "num_false_positives",
              "num_misses", "num_switches", "mota", "motp", "recall", "precision", "idf1", "idp",
              "idr", "idtp", "idfp", "idfn"]


# ----------------------------------------------------------------------------------------------
# Sequences: rows are kept as the text written to the files, so that every side parses the same.

class Sequence:
    def __init__(self, name):
        self.name = name
        self.gt = []          # [frame, id, x, y, w, h, flag, class, visibility] as strings
        self.pred = []        # [frame, id, x, y, w, h, conf] as strings
        self.layout = "seqinfo"  # seqinfo: seqinfo.ini; img1: img1/ (+ a wrong seqinfo.ini); none
        self.pred_format = "txt10"  # txt10, txt8, txt7 or jsonl
        self.length = 0       # N: frames evaluated

    def write_gt(self, root):
        folder = os.path.join(root, self.name)
        os.makedirs(os.path.join(folder, "gt"))
        rows = sorted(self.gt, key=lambda r: (int(r[1]), int(r[0])))  # MOT17's order: by id
        with open(os.path.join(folder, "gt", "gt.txt"), "w") as f:
            f.writelines(",".join(r) + "\n" for r in rows)
        if self.layout in ("seqinfo", "img1"):
            length = self.length if self.layout == "seqinfo" else self.length + 50  # img1/ wins
            with open(os.path.join(folder, "seqinfo.ini"), "w") as f:
                f.write("[Sequence]\nname=%s\nimDir=img1\nframeRate=30\nseqLength=%d\n"
                        "imWidth=1920\nimHeight=1080\nimExt=.jpg\n" % (self.name, length))
        if self.layout == "img1":
            os.makedirs(os.path.join(folder, "img1"))
            for i in range(1, self.length + 1):
                open(os.path.join(folder, "img1", "%06d.jpg" % i), "w").close()

    def write_pred(self, folder):
        if self.pred_format == "jsonl":
            path = os.path.join(folder, self.name + ".jsonl")
            frames = {}
            for r in self.pred:
                frames.setdefault(int(r[0]), []).append(
                    {"id": int(r[1]), "confidence": float(r[6]), "x": float(r[2]), "y": float(r[3]),
                     "w": float(r[4]), "h": float(r[5])})
            with open(path, "w") as f:
                for frame in range(1, max(frames) + 1):
                    if frame in frames or frame % 7 == 0:  # some empty frames written, some left out
                        f.write(json.dumps({"frame": frame - 1, "objects": frames.get(frame, [])}) + "\n")
            return path
        path = os.path.join(folder, self.name + ".txt")
        tail = {"txt10": ["-1", "-1", "-1"], "txt8": ["-1"], "txt7": []}[self.pred_format]
        with open(path, "w") as f:
            f.writelines(",".join(r + tail) + "\n" for r in self.pred)
        return path


def fmt(v):
    return repr(round(float(v), 2))


def synthetic_sequence(rng, name, layout, pred_format, minus_one_ids=False, zero_width_box=False):
    seq = Sequence(name)
    seq.layout, seq.pred_format = layout, pred_format
    n_frames = int(rng.integers(20, 61))
    n_people = int(rng.integers(5, 16))
    last_gt = n_frames if layout == "none" else n_frames - int(rng.integers(0, 3))
    no_gt_frame = int(rng.integers(3, last_gt - 3))

    def walk(start, end, w, h, pos=None):
        pos = np.array(pos if pos is not None else [rng.uniform(-20, 1900 - w), rng.uniform(0, 1080 - h)])
        vel = rng.normal(0, 4, 2)
        boxes = {}
        for f in range(start, end + 1):
            vel = 0.8 * vel + rng.normal(0, 2, 2)
            pos = pos + vel
            boxes[f] = (pos[0], pos[1], w, h)
        return boxes

    tracks = []  # (id, class, {frame: box}, flag-0 frames or all, visibility source)
    for pid in range(1, n_people + 1):
        start = 1 if rng.random() < 0.5 else int(rng.integers(1, last_gt - 5))
        end = last_gt if rng.random() < 0.5 else int(rng.integers(start + 5, last_gt + 1))
        w = float(rng.uniform(30, 110))
        boxes = walk(start, end, w, w * rng.uniform(2.2, 2.8))
        if rng.random() < 0.3:  # occluded for a few frames: no row at all
            g = int(rng.integers(start, end + 1))
            for f in range(g, g + int(rng.integers(1, 5))):
                boxes.pop(f, None)
        tracks.append((pid, 1, boxes))
    for k in range(int(rng.integers(1, 4))):  # distractors, the first one beside a pedestrian
        cls = int(rng.choice(DISTRACTOR_CLASSES))
        if k == 0:
            pid, _, host = tracks[int(rng.integers(n_people))]
            boxes = {f: (x + 0.25 * w, y + 0.1 * h, w, h) for f, (x, y, w, h) in host.items()}
        else:
            start = int(rng.integers(1, last_gt - 5))
            w = float(rng.uniform(30, 90))
            boxes = walk(start, last_gt, w, 2.5 * w)
        tracks.append((1000 + k, cls, boxes))
    for k in range(int(rng.integers(1, 3))):
        w = float(rng.uniform(60, 200))
        tracks.append((2000 + k, int(rng.choice(OTHER_CLASSES)), walk(1, last_gt, w, 0.6 * w)))

    gt_by_frame = {}
    for tid, cls, boxes in tracks:
        for f, (x, y, w, h) in boxes.items():
            if f == no_gt_frame:
                continue
            if cls == 1:
                flag = 0 if rng.random() < 0.06 else 1
                u = rng.random()
                vis = 0.5 if u < 0.05 else (round(float(rng.uniform(0, 0.5)), 5) if u < 0.3 else
                                            round(float(rng.uniform(0.5, 1)), 5))
            else:
                flag = int(rng.random() < 0.3) if cls in DISTRACTOR_CLASSES else 0
                vis = round(float(rng.uniform(0, 1)), 5)
            row = [str(f), str(tid), str(int(round(x))), str(int(round(y))), str(int(round(w))),
                   str(int(round(h))), str(flag), str(cls), repr(vis)]
            seq.gt.append(row)
            gt_by_frame.setdefault(f, []).append(row)
    seq.length = n_frames if layout != "none" else max(int(r[0]) for r in seq.gt)

    # Predictions
    ped_ids = [t[0] for t in tracks if t[1] == 1]
    relabel = {t[0]: (t[0] if t[1] == 1 else 600 + t[0]) for t in tracks}
    next_new_id, next_false_id = 100, 5000
    swaps_back = {}
    empty_frames = {int(rng.integers(2, n_frames))}
    if name.endswith("5"):
        empty_frames |= set(range(8, 13))  # a long stretch without predictions
    for f in range(1, seq.length + 3):  # two frames past the end: ignored
        for a, b in swaps_back.pop(f, []):
            relabel[a], relabel[b] = relabel[b], relabel[a]
        present = [int(r[1]) for r in gt_by_frame.get(f, []) if r[7] == "1"]
        if len(present) >= 2 and rng.random() < 0.1:  # two tracks exchange ids for some frames
            a, b = rng.choice(present, size=2, replace=False)
            relabel[a], relabel[b] = relabel[b], relabel[a]
            swaps_back.setdefault(f + int(rng.integers(2, 9)), []).append((a, b))
        if rng.random() < 0.06:  # a track breaks: new id from here on
            relabel[int(rng.choice(ped_ids))] = next_new_id
            next_new_id += 1
        if f in empty_frames:
            continue
        out = []
        for r in gt_by_frame.get(f, []):
            cls, flag = int(r[7]), int(r[6])
            keep = 0.9 if cls == 1 and flag else 0.8 if cls == 1 else 0.7 if cls in DISTRACTOR_CLASSES else 0.3
            if rng.random() > keep:
                continue
            x, y, w, h = (float(v) for v in r[2:6])
            u = rng.random()
            sd = 0.04 if u < 0.7 else 0.12 if u < 0.9 else 0.25
            box = (x + rng.normal(0, sd * w), y + rng.normal(0, sd * h),
                   max(2.0, w * (1 + rng.normal(0, sd))), max(2.0, h * (1 + rng.normal(0, sd))))
            out.append((relabel[int(r[1])], box))
        for _ in range(int(rng.poisson(0.6))):  # false boxes: anywhere or next to a person
            rows = gt_by_frame.get(f, [])
            if rows and rng.random() < 0.5:
                x, y, w, h = (float(v) for v in rows[int(rng.integers(len(rows)))][2:6])
                box = (x + rng.choice([-1, 1]) * rng.uniform(0.25, 0.6) * w, y + rng.normal(0, 0.1 * h), w, h)
            else:
                w = float(rng.uniform(30, 100))
                box = (rng.uniform(0, 1800), rng.uniform(0, 800), w, 2.5 * w)
            out.append((-1 if minus_one_ids else next_false_id, box))
            next_false_id += 1
        if zero_width_box and f == 5:
            rows = gt_by_frame.get(f, [])
            if rows:
                x, y, w, h = (float(v) for v in rows[0][2:6])
                out.append((next_false_id, (x, y, 0.0, h)))
                next_false_id += 1
        for pid, (x, y, w, h) in out:
            seq.pred.append([str(f), str(pid), fmt(x), fmt(y), fmt(w), fmt(h), fmt(rng.random())])
    if minus_one_ids:  # a few tracked boxes lose their id too
        for r in seq.pred:
            if rng.random() < 0.05:
                r[1] = "-1"
    return seq


def synthetic_sequences(seed):
    rng = np.random.default_rng(seed)
    plan = [("seqinfo", "txt10", {"zero_width_box": True}), ("img1", "txt10", {"minus_one_ids": True}),
            ("none", "txt7", {}), ("seqinfo", "jsonl", {}), ("img1", "txt8", {}),
            ("seqinfo", "txt10", {})]
    return [synthetic_sequence(rng, "SYN%d-%d" % (seed, i), layout, fmt_, **kw)
            for i, (layout, fmt_, kw) in enumerate(plan)]


def crafted_sequences():
    """Two sequences where TrackEval's CLEAR and motmetrics disagree by construction.
    CRAFT-1: gt 1 is matched to 10 in frame 1, missed in frame 2; from frame 3 on 10 overlaps it
    with IoU 0.61 and 11 with IoU 0.96. motmetrics keeps 10 (its last match), TrackEval takes 11
    (no continuation bonus after the gap) and counts a switch.
    CRAFT-2: in frame 2 three people side by side, a third of a width apart, and three boxes: two
    on the two right people and one further right. Matching all three uses IoU 0.50 pairs (sum
    1.51); TrackEval prefers the two exact pairs (sum 2.0), motmetrics the three matches."""
    one = Sequence("CRAFT-1")
    one.length = 6
    for f in range(1, 7):
        one.gt += [[str(f), "1", "100", "100", "50", "120", "1", "1", "1.0"],
                   [str(f), "2", "600", "100", "50", "120", "1", "1", "1.0"]]
        one.pred.append([str(f), "20", "600.0", "100.0", "50.0", "120.0", "0.9"])
        if f == 1:
            one.pred.append([str(f), "10", "100.0", "100.0", "50.0", "120.0", "0.9"])
        elif f >= 3:
            one.pred += [[str(f), "10", "112.0", "100.0", "50.0", "120.0", "0.9"],
                         [str(f), "11", "101.0", "100.0", "50.0", "120.0", "0.9"]]
    two = Sequence("CRAFT-2")
    two.length = 3
    for f in range(1, 4):
        two.gt.append([str(f), "1", "1000", "100", "50", "120", "1", "1", "1.0"])
        two.pred.append([str(f), "1", "1000.0", "100.0", "50.0", "120.0", "0.9"])
    for k, x in enumerate((100, 133, 166)):
        two.gt.append(["2", str(3 + k), str(x), "500", "100", "200", "1", "1", "1.0"])
        two.pred.append(["2", str(30 + k), "%d.0" % (x + 33), "500.0", "100.0", "200.0", "0.9"])
    return [one, two]


def mot17_sequences(train):
    seqs = []
    for name in sorted(os.listdir(train)):
        folder = os.path.join(train, name)
        if not os.path.isfile(os.path.join(folder, "gt", "gt.txt")):
            continue
        seq = Sequence(name)
        seq.gt = [l.strip().split(",") for l in open(os.path.join(folder, "gt", "gt.txt")) if l.strip()]
        seq.pred = [l.strip().split(",")[:7] for l in open(os.path.join(folder, "det", "det.txt")) if l.strip()]
        seq.length = len(os.listdir(os.path.join(folder, "img1")))
        seq.source = folder
        seqs.append(seq)
    return seqs


# ----------------------------------------------------------------------------------------------
# References

def reference_files(seq, min_score, min_visibility):
    """The gt and prediction rows TrackEval is given for what the tool's options mean."""
    gt = []
    for r in seq.gt:
        if int(float(r[0])) > seq.length:
            continue
        r = list(r)
        if r[7] == "1" and int(float(r[6])) != 0 and float(r[8]) < min_visibility:
            r[7] = "8"
        gt.append(r)
    pred = [list(r) for r in seq.pred if int(float(r[0])) <= seq.length and float(r[6]) >= min_score]
    next_id = max([int(float(r[1])) for r in pred] + [0]) + 1
    for r in pred:
        if int(float(r[1])) == -1:
            r[1] = str(next_id)
            next_id += 1
    return gt, pred


def run_trackeval(seqs, min_score, min_visibility, tmp):
    root = tempfile.mkdtemp(dir=tmp)
    for seq in seqs:
        gt, pred = reference_files(seq, min_score, min_visibility)
        os.makedirs(os.path.join(root, "gt", seq.name, "gt"))
        with open(os.path.join(root, "gt", seq.name, "gt", "gt.txt"), "w") as f:
            f.writelines(",".join(r) + "\n" for r in gt)
        os.makedirs(os.path.join(root, "trackers", "ref", "data"), exist_ok=True)
        with open(os.path.join(root, "trackers", "ref", "data", seq.name + ".txt"), "w") as f:
            f.writelines(",".join(r[:7] + ["-1", "-1", "-1"]) + "\n" for r in pred)
    log = io.StringIO()
    with contextlib.redirect_stdout(log):  # the metrics print their configuration
        dataset, evaluator, metrics = trackeval_setup(root, seqs)
    try:
        with contextlib.redirect_stdout(log):
            results, _ = evaluator.evaluate([dataset], metrics)
            data = {s.name: dataset.get_preprocessed_seq_data(dataset.get_raw_seq_data("ref", s.name),
                                                               "pedestrian") for s in seqs}
    except Exception:
        sys.stdout.write(log.getvalue())
        raise
    res = results["MotChallenge2DBox"]["ref"]
    return {k: v["pedestrian"] for k, v in res.items()}, data


def trackeval_setup(root, seqs):
    dataset = trackeval.datasets.MotChallenge2DBox({
        "GT_FOLDER": os.path.join(root, "gt"), "TRACKERS_FOLDER": os.path.join(root, "trackers"),
        "OUTPUT_FOLDER": os.path.join(root, "out"), "TRACKERS_TO_EVAL": ["ref"],
        "CLASSES_TO_EVAL": ["pedestrian"], "BENCHMARK": "MOT17", "SPLIT_TO_EVAL": "train",
        "SKIP_SPLIT_FOL": True, "SEQ_INFO": {s.name: s.length for s in seqs}, "DO_PREPROC": True,
        "PRINT_CONFIG": False})
    evaluator = trackeval.Evaluator({
        "USE_PARALLEL": False, "BREAK_ON_ERROR": True, "LOG_ON_ERROR": None, "PRINT_RESULTS": False,
        "PRINT_CONFIG": False, "TIME_PROGRESS": False, "OUTPUT_SUMMARY": False,
        "OUTPUT_DETAILED": False, "PLOT_CURVES": False})
    metrics = [trackeval.metrics.HOTA(), trackeval.metrics.CLEAR({"THRESHOLD": 0.5, "PRINT_CONFIG": False}),
               trackeval.metrics.Identity({"THRESHOLD": 0.5, "PRINT_CONFIG": False})]
    return dataset, evaluator, metrics


def accumulate(data):
    """motmetrics' accumulator over TrackEval's preprocessed sequence: distance 1 - IoU, IoU >= 0.5."""
    acc = mm.MOTAccumulator(auto_id=True)
    for t in range(data["num_timesteps"]):
        sim = np.asarray(data["similarity_scores"][t], dtype=float).reshape(
            len(data["gt_ids"][t]), len(data["tracker_ids"][t]))
        dist = 1.0 - sim
        dist[sim < 0.5] = np.nan
        acc.update(list(data["gt_ids"][t]), list(data["tracker_ids"][t]), dist)
    return acc


def pct(v):
    v = float(v)
    return None if math.isnan(v) else 100.0 * v


def expected_scores(mm_row, te, counts):
    e = dict(counts)
    e.update({
        "id_switches": int(mm_row["num_switches"]), "matches": int(mm_row["num_detections"]),
        "false_positives": int(mm_row["num_false_positives"]), "misses": int(mm_row["num_misses"]),
        "idtp": int(mm_row["idtp"]), "idfp": int(mm_row["idfp"]), "idfn": int(mm_row["idfn"]),
        "recall": pct(mm_row["recall"]), "precision": pct(mm_row["precision"]),
        "mota": pct(mm_row["mota"]), "idf1": pct(mm_row["idf1"]), "idp": pct(mm_row["idp"]),
        "idr": pct(mm_row["idr"]),
        # mean IoU of the CLEAR matches (TrackEval's MOTP definition) = 1 - motmetrics' MOTP
        "motp": pct(1.0 - float(mm_row["motp"])),
    })
    for key, field in HOTA_KEYS.items():
        e[key] = 100.0 * float(np.mean(te["HOTA"][field]))
    e["hota_alpha"] = [100.0 * float(v) for v in te["HOTA"]["HOTA"]]
    # sanity: the accumulator saw what TrackEval counted
    assert int(mm_row["num_objects"]) == counts["gt_dets"], (mm_row["num_objects"], counts)
    assert int(mm_row["num_predictions"]) == counts["pred_dets"], (mm_row["num_predictions"], counts)
    assert int(mm_row["num_frames"]) == counts["frames"], (mm_row["num_frames"], counts)
    return e


# ----------------------------------------------------------------------------------------------
# Where TrackEval's CLEAR and motmetrics disagree: find the first frame whose matches differ.

def trackeval_clear_matches(data):
    """Per frame, the (gt, tracker) matches of trackeval/metrics/clear.py CLEAR.eval_sequence (same
    code path: continuation bonus 1000 for the previous evaluated frame's match, IoU < 0.5 - eps
    zeroed, scipy's assignment maximising the score)."""
    from scipy.optimize import linear_sum_assignment
    eps = np.finfo("float").eps
    prev_step = {}
    frames = []
    for t in range(data["num_timesteps"]):
        g, h = data["gt_ids"][t], data["tracker_ids"][t]
        if len(g) == 0 or len(h) == 0:
            frames.append(set())
            continue
        sim = data["similarity_scores"][t]
        bonus = np.array([[prev_step.get(int(a)) == int(b) for b in h] for a in g])
        score = 1000 * bonus + sim
        score[sim < 0.5 - eps] = 0
        rows, cols = linear_sum_assignment(-score)
        ok = score[rows, cols] > 0 + eps
        matches = {(int(g[i]), int(h[j])) for i, j in zip(rows[ok], cols[ok])}
        prev_step = {a: b for a, b in matches}
        frames.append(matches)
    return frames


def motmetrics_matches(acc, num_frames):
    ev = acc.mot_events
    frames = [set() for _ in range(num_frames)]
    for (frame, _), row in ev[ev.Type.isin(["MATCH", "SWITCH"])].iterrows():
        frames[int(frame)].add((int(row.OId), int(row.HId)))
    return frames


def explain_clear_difference(data, acc):
    """None when TrackEval's and motmetrics' CLEAR matches are equal in every frame, else
    (frame, explained, text) for the first frame where they differ."""
    te = trackeval_clear_matches(data)
    mmf = motmetrics_matches(acc, data["num_timesteps"])
    last_match, prev_step = {}, {}
    for t, (a, b) in enumerate(zip(te, mmf)):
        g = data["gt_ids"][t]
        if a != b:
            sim = data["similarity_scores"][t]
            gi = {int(x): i for i, x in enumerate(g)}
            hi = {int(x): j for j, x in enumerate(data["tracker_ids"][t])}
            relinked = [(o, h) for o, h in b - a if last_match.get(o) == h and prev_step.get(o) != h]
            if relinked:
                o, h = relinked[0]
                return t + 1, True, (
                    "frame %d: motmetrics keeps gt %d on hypothesis %d (ids as TrackEval relabels them), its last match before a gap "
                    "(motmetrics/mot.py update step 1 re-establishes self.m), TrackEval's continuation "
                    "bonus covers only the previous evaluated frame (trackeval/metrics/clear.py: "
                    "score_mat from prev_timestep_tracker_id)" % (t + 1, o, h))
            if len(a) < len(b):
                return t + 1, True, (
                    "frame %d: TrackEval maximises the summed IoU and matches %d pairs, motmetrics "
                    "first maximises the number of matches (motmetrics/lap.py add_expensive_edges) "
                    "and matches %d" % (t + 1, len(a), len(b)))
            sa = sum(sim[gi[o], hi[h]] for o, h in a)
            sb = sum(sim[gi[o], hi[h]] for o, h in b)
            if len(a) == len(b) and abs(sa - sb) <= 1e-9:
                return t + 1, True, "frame %d: equal-cost tie, the two Hungarian solvers pick different " \
                                    "pairs" % (t + 1)
            return t + 1, False, "frame %d: TrackEval matches %s, motmetrics %s (IoU sums %.12g, %.12g)" % (
                t + 1, sorted(a - b), sorted(b - a), sa, sb)
        if len(g) and len(data["tracker_ids"][t]):
            prev_step = dict(a)
        last_match.update(dict(a))
    return None


# ----------------------------------------------------------------------------------------------

def close(want, got):
    if want is None or (isinstance(want, float) and math.isnan(want)):
        return got is None
    if got is None or isinstance(got, bool) or not isinstance(got, (int, float)):
        return False
    if isinstance(want, int):
        return got == want
    return abs(want - got) <= 1e-6


class Checker:
    def __init__(self, exe, tmp):
        self.exe, self.tmp = exe, tmp
        self.ok = True
        self.compared = 0
        self.notes = []

    def fail(self, text):
        print("    MISMATCH " + text)
        self.ok = False

    def references(self, seqs, min_score, min_visibility):
        te, data = run_trackeval(seqs, min_score, min_visibility, self.tmp)
        accs = [accumulate(data[s.name]) for s in seqs]
        names = [s.name for s in seqs]
        mh = mm.metrics.create()
        table = mh.compute_many(accs, metrics=MM_METRICS, names=names, generate_overall=True)
        want, extra = {}, {}
        total = {k: 0 for k in ("frames", "gt_dets", "pred_dets", "gt_ids", "pred_ids")}
        for s, acc in zip(seqs, accs):
            d = data[s.name]
            counts = {"frames": d["num_timesteps"], "gt_dets": d["num_gt_dets"],
                      "pred_dets": d["num_tracker_dets"], "gt_ids": d["num_gt_ids"],
                      "pred_ids": d["num_tracker_ids"]}
            for k in total:
                total[k] += counts[k]
            want[s.name] = expected_scores(table.loc[s.name], te[s.name], counts)
            extra[s.name] = (te[s.name], explain_clear_difference(d, acc))
        want[None] = expected_scores(table.loc["OVERALL"], te["COMBINED_SEQ"], total)
        diffs = [extra[n][1] for n in names if extra[n][1] is not None]
        extra[None] = (te["COMBINED_SEQ"], diffs[0] if diffs else None)
        return want, extra

    def run_tool(self, label, gt_arg, pred_arg, options):
        cmd = [self.exe, "--mot-gt", gt_arg, "--pred", pred_arg, "--json"] + options
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            self.fail("%s: jointflow-eval exited %d: %s\n      command: %s"
                      % (label, proc.returncode, proc.stderr.strip()[-2000:], " ".join(cmd)))
            return None
        try:
            return json.loads(proc.stdout)
        except ValueError as err:
            self.fail("%s: jointflow-eval printed no JSON (%s): %s" % (label, err, proc.stdout[:500]))
            return None

    def compare(self, label, got, want, extra, single=False):
        if got is None:
            return
        if not isinstance(got, dict) or "sequences" not in got or "combined" not in got:
            self.fail("%s: JSON without sequences/combined: %s" % (label, str(got)[:300]))
            return
        names = [n for n in want if n is not None]
        got_seqs = got["sequences"]
        if single:
            if len(got_seqs) != 1:
                self.fail("%s: a single-sequence run gave %d sequences" % (label, len(got_seqs)))
                return
            got_seqs = {names[0]: next(iter(got_seqs.values()))}
        elif sorted(got_seqs) != sorted(names):
            self.fail("%s: sequences %s, expected %s" % (label, sorted(got_seqs), sorted(names)))
        for name in names + [None]:
            where = "%s / %s" % (label, name or "combined")
            g = got["combined"] if name is None else got_seqs.get(name)
            if g is None:
                continue
            w = want[name]
            bad = 0
            for key in COUNT_KEYS + PERCENT_KEYS:
                self.compared += 1
                want_v, got_v = w[key], g.get(key, "(missing)")
                if key == "motp" and w["matches"] == 0 and got_v in (0, 0.0, None):
                    continue  # no matches: TrackEval's MOTP is 0, motmetrics' NaN; either is fine
                if not close(want_v, got_v):
                    src = "TrackEval" if key in HOTA_KEYS else "motmetrics" if key not in \
                        ("frames", "gt_dets", "pred_dets", "gt_ids", "pred_ids") else "TrackEval preproc"
                    self.fail("%s %s: %s %r, jointflow-eval %r" % (where, key, src, want_v, got_v))
                    bad += 1
            alphas = g.get("hota_alpha")
            self.compared += 1
            if not isinstance(alphas, list) or len(alphas) != 19:
                self.fail("%s hota_alpha: expected 19 values, jointflow-eval %r" % (where, alphas))
                bad += 1
            else:
                for a, (wv, gv) in enumerate(zip(w["hota_alpha"], alphas)):
                    if not close(wv, gv):
                        self.fail("%s hota_alpha[%d] (alpha %.2f): TrackEval %r, jointflow-eval %r"
                                  % (where, a, 0.05 * (a + 1), wv, gv))
                        bad += 1
            self.report_references(where, w, extra[name], bad)

    def report_references(self, where, w, extra, bad):
        te, diff = extra
        clear, ident = te["CLEAR"], te["Identity"]
        te_mota, te_idsw, te_idf1 = 100 * clear["MOTA"], int(clear["IDSW"]), 100 * ident["IDF1"]
        print("  %-34s MOTA %7.3f (TrackEval %7.3f)  IDSW %3d (%3d)  IDF1 %7.3f (%7.3f)  HOTA %7.3f  %s"
              % (where, w["mota"] if w["mota"] is not None else float("nan"), te_mota, w["id_switches"],
                 te_idsw, w["idf1"] if w["idf1"] is not None else float("nan"), te_idf1, w["hota"],
                 "ok" if not bad else "%d MISMATCHES" % bad))
        # Identity: both references solve the same global assignment on IoU >= 0.5 pairs.
        for key, te_key in (("idtp", "IDTP"), ("idfp", "IDFP"), ("idfn", "IDFN")):
            if int(ident[te_key]) != w[key]:
                self.fail("%s references disagree on %s: motmetrics %d, TrackEval %d"
                          % (where, key, w[key], int(ident[te_key])))
        same = (int(clear["CLR_TP"]) == w["matches"] and int(clear["CLR_FP"]) == w["false_positives"]
                and int(clear["CLR_FN"]) == w["misses"] and te_idsw == w["id_switches"])
        if diff is None:  # the matches are the same in every frame: so must the figures be
            if not same or (w["matches"] and abs(100 * clear["MOTP"] - w["motp"]) > 1e-6):
                self.fail("%s references disagree with equal matches: TrackEval TP/FP/FN/IDSW/MOTP "
                          "%d/%d/%d/%d/%.9f, motmetrics %d/%d/%d/%d/%.9f"
                          % (where, clear["CLR_TP"], clear["CLR_FP"], clear["CLR_FN"], te_idsw,
                             100 * clear["MOTP"], w["matches"], w["false_positives"], w["misses"],
                             w["id_switches"], w["motp"] or 0))
        else:
            frame, explained, text = diff
            if not explained:
                self.fail("%s references disagree, unexplained: %s" % (where, text))
            elif not same:
                note = "%s: TrackEval CLEAR differs from motmetrics (TP %d vs %d, IDSW %d vs %d); first " \
                       "at %s" % (where, clear["CLR_TP"], w["matches"], te_idsw, w["id_switches"], text)
                self.notes.append(note)
                print("    reference note: " + note)

    def case(self, label, seqs, options, min_score=0.0, min_visibility=0.5, single=None):
        """Writes the sequences, runs the tool on them (all, or the one named by single) and compares."""
        root = tempfile.mkdtemp(dir=self.tmp)
        gt_root, pred_root = os.path.join(root, "gt"), os.path.join(root, "pred")
        os.makedirs(gt_root)
        os.makedirs(pred_root)
        files = {}
        for s in seqs:
            if getattr(s, "source", None):
                files[s.name] = os.path.join(pred_root, s.name + ".txt")
                shutil.copyfile(os.path.join(s.source, "det", "det.txt"), files[s.name])
            else:
                s.write_gt(gt_root)
                files[s.name] = s.write_pred(pred_root)
        if single is not None:
            seqs = [s for s in seqs if s.name == single]
        want, extra = self.references(seqs, min_score, min_visibility)
        src = getattr(seqs[0], "source", None)
        if single is not None:
            gt_arg = src or os.path.join(gt_root, single)
            if src:
                files[single] = os.path.join(src, "det", "det.txt")
            pred_arg = files[single]
        else:
            gt_arg = os.path.dirname(src) if src else gt_root
            pred_arg = pred_root
        print("%s (%s)" % (label, " ".join(options) or "defaults"))
        self.compare(label, self.run_tool(label, gt_arg, pred_arg, options), want, extra,
                     single=single is not None)


def main():
    exe = sys.argv[1]
    data = sys.argv[2] if len(sys.argv) > 2 else os.environ.get("JOINTFLOW_DATA", "")
    try:
        helptext = subprocess.run([exe, "--help"], capture_output=True, text=True).stdout
    except OSError as err:
        print("SKIPPED: cannot run %s: %s" % (exe, err))
        return 77
    if not re.search(r"^\s*--mot-gt\b", helptext, re.MULTILINE):  # an option line, not a mention
        print("SKIPPED: %s has no --mot-gt option (MOT evaluation not built)" % exe)
        return 77
    skipped = False
    with tempfile.TemporaryDirectory() as tmp:
        c = Checker(exe, tmp)
        for seed in (1, 2):
            seqs = synthetic_sequences(seed)
            c.case("synthetic seed %d raw" % seed, seqs, ["--min-visibility", "0"], 0.0, 0.0)
            c.case("synthetic seed %d" % seed, seqs, [], 0.0, 0.5)
        seqs = synthetic_sequences(3)
        c.case("synthetic seed 3 score 0.3 vis 0.3", seqs,
               ["--min-score", "0.3", "--min-visibility", "0.3", "--iou", "0.5"], 0.3, 0.3)
        c.case("synthetic seed 3 one .jsonl", seqs, [], 0.0, 0.5, single=seqs[3].name)
        c.case("synthetic seed 3 one .txt (ids -1)", seqs, ["--min-visibility", "0"], 0.0, 0.0,
               single=seqs[1].name)
        c.case("crafted: TrackEval's CLEAR differs", crafted_sequences(), [], 0.0, 0.5)
        train = os.path.join(data, "mot17-mini", "train") if data else ""
        if train and os.path.isdir(train):
            seqs = mot17_sequences(train)
            c.case("MOT17 det/det.txt", seqs, ["--min-score", "0.5"], 0.5, 0.5)
            c.case("MOT17 det/det.txt raw", seqs, ["--min-score", "0.5", "--min-visibility", "0"], 0.5, 0.0)
            c.case("MOT17-09 alone", seqs, ["--min-score", "0.5"], 0.5, 0.5, single="MOT17-09-FRCNN")
        else:
            print("SKIPPED the MOT17 cases: %s is absent (set JOINTFLOW_DATA)" % (train or "mot17-mini/train"))
            skipped = True
    print("compared %d figures with py-motmetrics %s (CLEAR MOT, identity) and TrackEval %s (HOTA); %s"
          % (c.compared, mm.__version__, trackeval.__version__, "all equal" if c.ok else "MISMATCHES"))
    if c.notes:
        print("%d sequence(s) where TrackEval's CLEAR differs from motmetrics' for the reasons noted above"
              % len(c.notes))
    return 1 if not c.ok else (77 if skipped else 0)


if __name__ == "__main__":
    sys.exit(main())
