"""A live run of jointflow-track against the tests' RTSP camera, watched from outside.

The camera is jointflow-rtsp-test-server (tests/rtsp: vtest.avi looped as live H.264 in real time,
optionally faster with --fps). jointflow-track tracks it with --metrics-port, and every
--sample-every seconds this script reads the process from /proc (resident memory, threads, open
file descriptors) and scrapes /metrics (frames in, dropped, tracked, inferred, reconnects). With
--outage-every the camera is killed (SIGKILL: the connection drops as in a power cut) and started
again on its port after each of --outage-lengths in turn, the scene going on meanwhile (the
server's --epoch). With --lag, jointflow-track writes each frame's lag (--output-lag).

    live_run.py --build build --duration 600 --out DIR [--fps 30] [--lag]
                [--outage-every 600 --outage-lengths 3,30] [-- jointflow-track options]

Writes DIR/samples.csv, DIR/lag.csv (with --lag), DIR/metrics.txt (the last scrape),
DIR/track.log, DIR/server.log and DIR/run.json (the command, the duration, the outages). Exit status 77 (SKIP) when the camera
cannot run here (no RTSP server library or H.264 encoder), 1 when jointflow-track fails.
"""
import argparse
import csv
import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request

SKIP = 77


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def proc_figures(pid: int) -> dict:
    """Resident memory (KiB), threads and open file descriptors of @pid, from /proc."""
    figures = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            key, _, value = line.partition(":")
            if key == "VmRSS":
                figures["rss_kib"] = int(value.split()[0])
            elif key == "Threads":
                figures["threads"] = int(value)
    figures["fds"] = len(os.listdir(f"/proc/{pid}/fd"))
    return figures


METRICS = {
    "frames_in": "jointflow_frames_in_total",
    "frames_dropped": "jointflow_frames_dropped_total",
    "frames_tracked": "jointflow_frames_tracked_total",
    "frames_inferred": "jointflow_frames_inferred_total",
    "tracks_created": "jointflow_tracks_created_total",
    "reconnects": "jointflow_reconnects_total",
    "lag_count": "jointflow_lag_seconds_count",
    "lag_sum": "jointflow_lag_seconds_sum",
}


def scrape(port: int) -> dict:
    """The samples of /metrics named in METRICS ("" where absent or nothing answered)."""
    values = {k: "" for k in METRICS}
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=5) as r:
            text = r.read().decode()
    except OSError:
        return values
    samples = {}
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, _, value = line.rpartition(" ")
            samples[name] = value
    for key, name in METRICS.items():
        values[key] = samples.get(name, "")
    return values


class Camera:
    def __init__(self, build: str, out: str, fps: float):
        self.port = free_port()
        self.epoch = time.time()
        self.argv = [os.path.join(build, "tests/rtsp/jointflow-rtsp-test-server"),
                     "--port", str(self.port), "--epoch", repr(self.epoch)]
        if fps > 0:
            self.argv += ["--fps", str(fps)]
        self.log = open(os.path.join(out, "server.log"), "a")
        self.process = None

    def start(self) -> None:
        self.process = subprocess.Popen(self.argv, stdout=subprocess.PIPE, stderr=self.log,
                                        text=True)
        line = self.process.stdout.readline()  # "ready rtsp://..." once it listens
        self.log.write(line)
        self.log.flush()
        if not line.startswith("ready"):
            status = self.process.wait(timeout=10)
            if status == SKIP:
                print(f"SKIP: the RTSP camera cannot run here: {line.strip()}")
                sys.exit(SKIP)
            sys.exit(f"the RTSP camera did not start (exit {status}); see server.log")

    def kill(self) -> None:
        self.process.send_signal(signal.SIGKILL)
        self.process.wait()

    def stop(self) -> None:
        if self.process and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.kill()

    @property
    def uri(self) -> str:
        return f"rtsp://127.0.0.1:{self.port}/stream"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--duration", type=float, required=True, help="seconds of live run")
    parser.add_argument("--out", required=True, help="folder for the CSV files and logs")
    parser.add_argument("--fps", type=float, default=0, help="camera frame rate (0: vtest's 10)")
    parser.add_argument("--lag", action="store_true", help="each frame's lag to lag.csv")
    parser.add_argument("--sample-every", type=float, default=5.0)
    parser.add_argument("--outage-every", type=float, default=0, help="seconds; 0 = none")
    parser.add_argument("--outage-lengths", default="3,30",
                        help="seconds of each outage, in turn (comma-separated)")
    parser.add_argument("track_args", nargs="*", help="more jointflow-track options (after --)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    build = os.path.abspath(args.build)
    for f in ("lag.csv", "samples.csv", "server.log", "track.log"):
        if os.path.exists(os.path.join(args.out, f)):
            os.remove(os.path.join(args.out, f))

    load_start = open("/proc/loadavg").read().split()[0]
    camera = Camera(build, args.out, args.fps)
    camera.start()
    metrics_port = free_port()
    argv = [os.path.join(build, "apps/jointflow-track"), camera.uri, "--quiet",
            "--metrics-port", str(metrics_port), "--metrics-address", "127.0.0.1",
            "--reconnect-attempts", "0"]
    if args.lag:
        argv += ["--output-lag", os.path.join(args.out, "lag.csv")]
    argv += args.track_args
    env = dict(os.environ, GST_PLUGIN_PATH=os.path.join(build, "gst-plugin"),
               GST_REGISTRY=os.path.join(build, "bench", "live-registry.bin"))
    track_log = open(os.path.join(args.out, "track.log"), "w")
    track = subprocess.Popen(argv, stdout=track_log, stderr=subprocess.STDOUT, env=env)
    start = time.monotonic()
    lengths = [float(x) for x in args.outage_lengths.split(",") if x]
    outages = []  # [start, end] in seconds from the start
    next_outage = args.outage_every if args.outage_every > 0 else float("inf")
    status = 0
    with open(os.path.join(args.out, "samples.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t", "rss_kib", "threads", "fds", *METRICS.keys(), "camera_up"])
        next_sample = 0.0
        down_until = None
        while True:
            now = time.monotonic() - start
            if now >= args.duration or track.poll() is not None:
                break
            if down_until is None and now >= next_outage:
                length = lengths[len(outages) % len(lengths)]
                camera.kill()
                outages.append([round(now, 1), None])
                down_until = now + length
                print(f"{now:7.1f} s: camera down for {length:g} s", flush=True)
            if down_until is not None and now >= down_until:
                camera.start()
                outages[-1][1] = round(now, 1)
                down_until = None
                next_outage += args.outage_every
                print(f"{now:7.1f} s: camera back", flush=True)
            if now >= next_sample:
                row = {"t": round(now, 2), **proc_figures(track.pid), **scrape(metrics_port),
                       "camera_up": int(down_until is None)}
                writer.writerow([row["t"], row["rss_kib"], row["threads"], row["fds"],
                                 *(row[k] for k in METRICS), row["camera_up"]])
                f.flush()
                next_sample += args.sample_every
            time.sleep(0.2)
    if track.poll() is None:
        # The last page of /metrics, whole (histograms and all), for the record.
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{metrics_port}/metrics",
                                        timeout=5) as r:
                with open(os.path.join(args.out, "metrics.txt"), "wb") as page:
                    page.write(r.read())
        except OSError:
            pass
        track.send_signal(signal.SIGTERM)
        try:
            status = track.wait(timeout=30)
        except subprocess.TimeoutExpired:
            track.kill()
            status = -1
    else:
        status = track.returncode
        print(f"jointflow-track ended early (exit {status}); see {args.out}/track.log")
    camera.stop()
    with open(os.path.join(args.out, "run.json"), "w") as f:
        json.dump({"command": argv, "camera": camera.argv, "duration": args.duration,
                   "outage_every": args.outage_every, "outage_lengths": lengths,
                   "load": f"{load_start} at the start, "
                           f"{open('/proc/loadavg').read().split()[0]} at the end (2 cores)",
                   "seconds": round(time.monotonic() - start, 1), "outages": outages,
                   "exit": status}, f, indent=1)
    return 0 if status == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
