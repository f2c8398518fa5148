"""Plots the resident memory of a soak run (bench/soak.sh): soak-rss.csv -> PNG.

    python plot_rss.py rss.csv out.png "title"
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> None:
    path, out, title = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    frames = [int(r["frame"]) for r in rows]
    mib = [int(r["rss_kib"]) / 1024.0 for r in rows]
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(frames, mib, marker=".", linewidth=1)
    ax.set_xlabel("frame")
    ax.set_ylabel("resident memory (MiB)")
    ax.set_title(title)
    ax.set_ylim(0, max(mib) * 1.15)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
