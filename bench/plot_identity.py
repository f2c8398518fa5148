"""Plots the identity benchmark (bench/identity.cpp): identity.json -> PNG of joint id switches and
MOTA per case, one bar per similarity, so that where each similarity loses ids shows at a glance.

    python plot_identity.py identity.json out.png
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ORDER = ["tff", "oks", "iou", "pckh", "flow"]


def main() -> None:
    path, out = sys.argv[1], sys.argv[2]
    with open(path) as f:
        doc = json.load(f)
    rows = doc.get("bonn_cases", [])
    if not rows:
        sys.exit(f"plot_identity: {path} has no Bonn cases to plot")
    cases = list(dict.fromkeys(r["case"] for r in rows))
    present = {r["similarity"] for r in rows}
    similarities = [s for s in ORDER if s in present] + sorted(present - set(ORDER))
    value = {(r["case"], r["similarity"]): r["total"] for r in rows}

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(14, 7), sharex=True)
    width = 0.8 / len(similarities)
    for i, similarity in enumerate(similarities):
        xs = [c + (i - (len(similarities) - 1) / 2) * width for c in range(len(cases))]
        totals = [value.get((case, similarity)) for case in cases]
        # id switches on a log axis: 0 is drawn at 0.5 so that a perfect case still shows a stub.
        switches = [max(t["id_switches"], 0.5) if t else 0 for t in totals]
        top.bar(xs, switches, width, label=similarity)
        bottom.bar(xs, [t["mota"] if t else 0 for t in totals], width, label=similarity)
    top.set_yscale("log")
    top.set_ylim(bottom=0.4)
    top.set_ylabel("joint id switches (log; 0 drawn at 0.5)")
    top.set_title("Identity benchmark: Bonn test sequence and its variants, per similarity")
    top.legend(ncol=len(similarities), fontsize=9)
    top.grid(True, axis="y", alpha=0.3)
    bottom.set_ylabel("MOTA (%)")
    bottom.set_ylim(0, 100)
    bottom.grid(True, axis="y", alpha=0.3)
    bottom.set_xticks(range(len(cases)))
    bottom.set_xticklabels(cases, rotation=20)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
