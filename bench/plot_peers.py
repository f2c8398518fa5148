"""Plots bench/peer_trackers.py's id changes: peer-trackers.json -> PNG with one row per tracker
and a tick at each frame where a labelled visit's id changed, the sign's frames shaded, so that
where each tracker loses ids shows at a glance.

    python plot_peers.py peer-trackers.json out.png SIGN_LAST_FRAME
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> None:
    path, out, sign_last = sys.argv[1], sys.argv[2], int(sys.argv[3])
    with open(path) as f:
        runs = json.load(f)["runs"]
    fig, ax = plt.subplots(figsize=(12, 0.45 * len(runs) + 1.2))
    ax.axvspan(1, sign_last, color="0.9")
    for row, r in enumerate(runs):
        frames = r["id_changes"]["frames"]
        ax.scatter(frames, [row] * len(frames), marker="|", s=160, color="tab:red")
        ax.text(801, row, " %d / %d" % (r["id_changes"]["sign"], r["id_changes"]["after"]),
                va="center", fontsize=8)
    ax.set_yticks(range(len(runs)))
    ax.set_yticklabels([r["tracker"] for r in runs], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(1, 800)
    ax.set_xlabel("frame of vtest.avi (10 frames/s); right: id changes at the sign / after it")
    ax.set_title("Where each tracker changes a labelled visit's id (same poses, our labels; "
                 "shaded: the sign, frames 1-%d)" % sign_last, fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
