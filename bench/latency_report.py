"""The report of the live latency benchmark (bench/live_bench.sh latency): each frame's lag, from its
capture to its poses leaving jointflowtrack (jointflow-track --output-lag), per minute and over
the whole run, against the engine's frame interval.

    latency_report.py RUN_DIR docs/latency.png docs/latency.md docs/latency.csv "command"

The engine's frame interval is the time between two frames leaving the tracker (the run's length
over the frames out): with a camera faster than the engine the tracker is never idle, so that is
what one frame costs it. Quantiles by nearest rank.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from run_section import write_run_section  # noqa: E402


def quantile(sorted_values, q):
    return sorted_values[max(0, math.ceil(q * len(sorted_values)) - 1)]


def summary(times, lags):
    s = sorted(lags)
    interval = (times[-1] - times[0]) / (len(times) - 1) if len(times) > 1 else float("nan")
    return {"frames": len(lags), "interval": interval, "p50": quantile(s, 0.5),
            "p90": quantile(s, 0.9), "p99": quantile(s, 0.99), "max": s[-1]}


def capture_text(captures):
    if not captures:
        return "none: the camera sent no capture time"
    return (f"{quantile(captures, 0.5) * 1000:.0f} / {quantile(captures, 0.99) * 1000:.0f} ms "
            f"({len(captures)} frames)")


def main() -> None:
    run_dir, png, md, table, command = sys.argv[1:6]
    with open(os.path.join(run_dir, "lag.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(run_dir, "samples.csv"), newline="") as f:
        samples = [r for r in csv.DictReader(f) if r["frames_in"]]
    with open(os.path.join(run_dir, "run.json")) as f:
        run = json.load(f)
    t0 = float(rows[0]["unix_time"])
    times = [float(r["unix_time"]) - t0 for r in rows]
    lags = [float(r["lag_seconds"]) for r in rows]
    # The camera's own capture time, where its RTCP sender reports gave one (frame_lag.hpp).
    captures = sorted(float(r["capture_lag_seconds"]) for r in rows
                      if r.get("capture_lag_seconds"))

    minutes = []
    for m in range(int(times[-1] // 60) + 1):
        idx = [i for i, t in enumerate(times) if m * 60 <= t < (m + 1) * 60]
        if len(idx) < 2:
            continue
        s = summary([times[i] for i in idx], [lags[i] for i in idx])
        if times[idx[-1]] - times[idx[0]] < 50:  # a partial last minute
            continue
        s["minute"] = m + 1
        minutes.append(s)
    total = summary(times, lags)
    n = len(times)
    first = sorted(lags[: n // 10])
    last = sorted(lags[-(n // 10):])
    slope = (sum((t - sum(times) / n) * (y - sum(lags) / n) for t, y in zip(times, lags)) /
             sum((t - sum(times) / n) ** 2 for t in times)) * 60.0

    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["minute", "frames_out", "engine_interval_s", "p50_s", "p90_s", "p99_s",
                    "max_s"])
        for s in minutes:
            w.writerow([s["minute"], s["frames"], f"{s['interval']:.4f}", f"{s['p50']:.4f}",
                        f"{s['p90']:.4f}", f"{s['p99']:.4f}", f"{s['max']:.4f}"])

    fig, (ax, hist) = plt.subplots(2, 1, figsize=(9, 7), gridspec_kw={"height_ratios": [2, 1]})
    ax.plot([t / 60 for t in times], [x * 1000 for x in lags], ".", markersize=2, alpha=0.4,
            label="each frame")
    mid = [s["minute"] - 0.5 for s in minutes]
    ax.plot(mid, [s["p50"] * 1000 for s in minutes], "-o", label="p50 per minute")
    ax.plot(mid, [s["p99"] * 1000 for s in minutes], "-o", label="p99 per minute")
    ax.plot(mid, [2 * s["interval"] * 1000 for s in minutes], "--", color="red",
            label="2 engine frame intervals (target for p99)")
    ax.set_xlabel("minutes")
    ax.set_ylabel("lag (ms)")
    top = max([max(lags), 2 * total["interval"]] + [2 * s["interval"] for s in minutes])
    ax.set_ylim(0, top * 1000 * 1.1)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("Lag from capture to poses, live RTSP camera faster than the engine")
    hist.hist([x * 1000 for x in lags], bins=60)
    hist.axvline(total["p99"] * 1000, color="orange", label=f"p99 {total['p99'] * 1000:.0f} ms")
    hist.axvline(2 * total["interval"] * 1000, color="red", linestyle="--",
                 label=f"2 intervals {2 * total['interval'] * 1000:.0f} ms")
    hist.set_xlabel("lag (ms)")
    hist.set_ylabel("frames")
    hist.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=100)

    last_sample = samples[-1]
    ok = total["p99"] <= 2 * total["interval"]
    per_minute_ok = sum(s["p99"] <= 2 * s["interval"] for s in minutes)
    lines = "\n".join(
        f"| {s['minute']} | {s['frames']} | {s['interval'] * 1000:.0f} | {s['p50'] * 1000:.0f} "
        f"| {s['p90'] * 1000:.0f} | {s['p99'] * 1000:.0f} | {s['max'] * 1000:.0f} "
        f"| {s['p99'] / s['interval']:.2f} |" for s in minutes)
    text = f"""## This run

Command: `{command}` ({run['seconds'] / 60:.1f} min; load average {run.get('load', '?')}).

![lag per frame and per minute](latency.png)

| | whole run |
|---|---|
| frames from the camera / dropped by the leaky queue / tracked | {last_sample['frames_in']} / {last_sample['frames_dropped']} / {last_sample['frames_tracked']} (at the last scrape) |
| frames out (with a lag) | {total['frames']} |
| engine frame interval | {total['interval'] * 1000:.0f} ms ({1 / total['interval']:.1f} frames/s against the camera's 30) |
| lag p50 / p90 / p99 / max | {total['p50'] * 1000:.0f} / {total['p90'] * 1000:.0f} / **{total['p99'] * 1000:.0f}** / {total['max'] * 1000:.0f} ms |
| p99 in engine frame intervals | **{total['p99'] / total['interval']:.2f}** (target <= 2: {'met' if ok else 'missed'}) |
| minutes with p99 <= 2 of their intervals | {per_minute_ok} of {len(minutes)} |
| median lag, first tenth / last tenth of the run | {quantile(first, 0.5) * 1000:.0f} / {quantile(last, 0.5) * 1000:.0f} ms |
| trend (least squares over every frame) | {slope * 1000:+.2f} ms per minute |
| capture lag p50 / p99 (from the camera's RTCP time, same host clock) | {capture_text(captures)} |

Per minute (ms; `docs/latency.csv`):

| minute | frames out | engine interval | p50 | p90 | p99 | max | p99 / interval |
|---|---|---|---|---|---|---|---|
{lines}
"""
    write_run_section(md, text)


if __name__ == "__main__":
    main()
