#!/usr/bin/env bash
# `make demo`: tracks the people in vtest.avi (ships with Debian's opencv-doc) with
# jointflow-track, writing out/vtest-tracked.mp4 (skeletons, ids, trails) and out/vtest.jsonl
# (poses per frame), and prints the summary.
#
# JOINTFLOW_DEMO_FRAMES (default 300 of the clip's 795 frames) keeps the run to about two minutes
# on two CPU cores (docs/gstreamer.md has the measurement); 0 tracks the whole clip.
set -euo pipefail
build=${1:-build}
video=${JOINTFLOW_VTEST:-/usr/share/doc/opencv-doc/examples/data/vtest.avi}
frames=${JOINTFLOW_DEMO_FRAMES:-300}
[ -f "$video" ] || { echo "demo: $video is missing (Debian package opencv-doc)" >&2; exit 1; }
mkdir -p out
"$build/apps/jointflow-track" "$video" --max-frames "$frames" \
  --output-video out/vtest-tracked.mp4 --output-json out/vtest.jsonl
