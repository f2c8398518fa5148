"""The report of a long live run (bench/live_bench.sh soak): resident memory, threads and open file
descriptors of jointflow-track over time, sampled from /proc by bench/live_run.py.

    soak_live_report.py RUN_DIR docs/soak-live.png docs/soak-live.md "command"

Growth is judged after the first 5 minutes (models loaded, allocator pools and caches filled):
resident memory by the slope of a least-squares line (MiB per hour), by its range, and by the
median of each 10 minutes (a sample can fall between a frame's buffers being freed and taken
again, so single samples dip by tens of MiB and tilt the line: the medians show the plateau);
threads and
file descriptors by their range among the samples taken while frames came (during an outage
and the reconnection after it the source's threads and sockets are gone, by design).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from run_section import write_run_section  # noqa: E402

WARMUP = 300.0  # seconds
WINDOW = 600.0  # seconds: the windows whose medians are reported


def window_medians(ts, ys):
    """The median of ys in each WINDOW of ts, from the first t on."""
    out = []
    start = ts[0]
    while start <= ts[-1]:
        vals = sorted(y for t, y in zip(ts, ys) if start <= t < start + WINDOW)
        if vals:
            out.append(vals[len(vals) // 2])
        start += WINDOW
    return out


def slope_per_hour(ts, ys):
    n = len(ts)
    mt, my = sum(ts) / n, sum(ys) / n
    den = sum((t - mt) ** 2 for t in ts)
    return 3600.0 * sum((t - mt) * (y - my) for t, y in zip(ts, ys)) / den if den else 0.0


def main() -> None:
    run_dir, png, md, command = sys.argv[1:5]
    with open(os.path.join(run_dir, "samples.csv"), newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["frames_in"]]
    with open(os.path.join(run_dir, "run.json")) as f:
        run = json.load(f)
    t = [float(r["t"]) for r in rows]
    mib = [int(r["rss_kib"]) / 1024.0 for r in rows]
    threads = [int(r["threads"]) for r in rows]
    fds = [int(r["fds"]) for r in rows]
    after = [i for i, x in enumerate(t) if x >= WARMUP] or list(range(len(t)))
    # Streaming: frames came since the previous sample, the camera up at both.
    up = [i for i in after if i > 0 and rows[i]["camera_up"] == rows[i - 1]["camera_up"] == "1"
          and int(rows[i]["frames_in"]) > int(rows[i - 1]["frames_in"])]
    slope = slope_per_hour([t[i] for i in after], [mib[i] for i in after])
    medians = window_medians([t[i] for i in after], [mib[i] for i in after])
    last = rows[-1]

    fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    minutes = [x / 60 for x in t]
    for ax, ys, label in ((axes[0], mib, "resident memory (MiB)"), (axes[1], threads, "threads"),
                          (axes[2], fds, "open file descriptors")):
        ax.plot(minutes, ys, linewidth=1)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        for start, end in run["outages"]:
            ax.axvspan(start / 60, (end if end is not None else t[-1]) / 60, color="red",
                       alpha=0.15, linewidth=0)
    axes[0].set_ylim(0, max(mib) * 1.15)
    axes[1].set_ylim(0, max(threads) * 1.3)
    axes[2].set_ylim(0, max(fds) * 1.3)
    axes[2].set_xlabel("minutes (red: camera down)")
    axes[0].set_title(f"jointflow-track on a live RTSP camera, {run['seconds'] / 60:.0f} min, "
                      f"{len(run['outages'])} outages")
    fig.tight_layout()
    fig.savefig(png, dpi=100)

    def span(values, idx):
        return f"{min(values[i] for i in idx)}-{max(values[i] for i in idx)}"

    text = f"""## This run

Command: `{command}` (load average {run.get('load', '?')}).

![resident memory, threads and file descriptors](soak-live.png)

| | this run |
|---|---|
| length | {run['seconds'] / 60:.1f} min, {len(t)} samples, every {float(rows[1]['t']) - float(rows[0]['t']):.0f} s |
| outages (start-end, s) | {', '.join(f'{a:.0f}-{b:.0f}' for a, b in run['outages'] if b) or 'none'} |
| frames in / dropped / tracked | {last['frames_in']} / {last['frames_dropped']} / {last['frames_tracked']} |
| reconnections (`jointflow_reconnects_total`) | {last['reconnects']} |
| track ids given out | {last['tracks_created']} |
| resident memory after 5 min: slope | **{slope:+.2f} MiB/hour** (target < 5) |
| resident memory after 5 min: range | {min(mib[i] for i in after):.1f}-{max(mib[i] for i in after):.1f} MiB |
| resident memory, median of each 10 min after 5 min | {', '.join(f'{m:.1f}' for m in medians)} MiB (last - first: {medians[-1] - medians[0]:+.1f} MiB) |
| threads after 5 min, streaming | {span(threads, up) if up else 'n/a'} (all samples: {span(threads, after)}) |
| open file descriptors after 5 min, streaming | {span(fds, up) if up else 'n/a'} (all samples: {span(fds, after)}) |
| exit status at SIGTERM | {run['exit']} |

The samples are in `docs/soak-live.csv`.
"""
    write_run_section(md, text)


if __name__ == "__main__":
    main()
