"""The tables of `make bench-spatial` (bench/spatial_recall.sh): per spatial option, recall and
precision on each MOT17-mini scene, the combined tracking figures, and vtest.avi's frames/s.

usage: spatial_recall_table.py RESULTS.jsonl FRCNN.json OUT.md OUT.json
"""
import json
import os
import sys


def pct(v):
    return "-" if v is None else f"{v:.1f}"


def main(results_path, frcnn_path, md_path, json_path):
    runs = [json.loads(line) for line in open(results_path)]
    frcnn = json.load(open(frcnn_path))
    scenes = list(frcnn["sequences"])
    lines = [
        "# Person recall of the spatial options on MOT17-mini",
        "",
        "Written by `make bench-spatial` (bench/spatial_recall.sh). A person counts as found when an",
        "output box overlaps a pedestrian of the ground truth (class 1, flag 1, visibility >= 0.5)",
        "at IoU >= 0.5, one to one; predictions on distractors (static people, reflections, people",
        "on vehicles) and on pedestrians less than half visible are left out (TrackEval's MOT17",
        "preprocessing, jointflow-eval --mot-gt). Engine: OpenVINO, this machine (2 cores).",
        "vtest.avi: 795 frames at 768x576, the whole `jointflow-track` process timed; load average",
        f"{os.environ.get('LOAD', 'not recorded')} (1 minute) over the run.",
        "",
        "## Recall / precision per scene, percent",
        "",
        "| option | " + " | ".join(s.replace("-FRCNN", "") for s in scenes) + " | all | vtest.avi frames/s |",
        "|---|" + "---:|" * (len(scenes) + 2),
    ]

    def row(name, scores, fps):
        cells = [f"{pct(scores['sequences'][s]['recall'])} / {pct(scores['sequences'][s]['precision'])}"
                 for s in scenes]
        c = scores["combined"]
        return (f"| {name} | " + " | ".join(cells) +
                f" | **{pct(c['recall'])}** / {pct(c['precision'])} | {fps} |")

    for r in runs:
        lines.append(row(r["name"], r["scores"], f"{r['vtest_fps']:.1f}"))
    lines.append(row("Faster R-CNN (MOT17 det.txt, score >= 0.5)", frcnn, "-"))
    lines += [
        "",
        "## Tracking on the same frames (4-8 frames a scene: MOTA and HOTA, not identity over time)",
        "",
        "| option | MOTA | MOTP | IDF1 | HOTA | DetA | AssA | id switches |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in runs:
        c = r["scores"]["combined"]
        lines.append(f"| {r['name']} | {pct(c['mota'])} | {pct(c['motp'])} | {pct(c['idf1'])} | "
                     f"{pct(c['hota'])} | {pct(c['deta'])} | {pct(c['assa'])} | {c['id_switches']} |")
    lines += ["", "Options:", ""]
    for r in runs:
        lines.append(f"- {r['name']}: `jointflow-track DIR/img1 {r['args']}`")
    open(md_path, "w").write("\n".join(lines) + "\n")
    json.dump({"options": runs, "faster_rcnn": frcnn}, open(json_path, "w"), indent=1)


if __name__ == "__main__":
    main(*sys.argv[1:])
