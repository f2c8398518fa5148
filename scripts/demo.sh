#!/usr/bin/env bash
# `make demo`: tracks the people in vtest.avi (ships with Debian's opencv-doc) with
# jointflow-track, writing out/vtest-tracked.mp4 (skeletons, ids, trails) and out/vtest.jsonl
# (poses per frame), and prints the summary.
#
# JOINTFLOW_DEMO_FRAMES (default 300 of the clip's 795 frames) keeps the run short on two CPU
# cores (docs/gstreamer.md has the measurement); 0 tracks the whole clip.
set -euo pipefail
build=${1:-build}
video=${JOINTFLOW_VTEST:-/usr/share/doc/opencv-doc/examples/data/vtest.avi}
frames=${JOINTFLOW_DEMO_FRAMES:-300}
[ -f "$video" ] || { echo "demo: $video is missing (Debian package opencv-doc)" >&2; exit 1; }
mkdir -p out
# OpenVINO where the build has it (`make build` installs it): since tiles are on by default the
# network runs three times a frame of vtest.avi, about 16 frames/s there against about 2 on
# cv::dnn (docs/tiles.md); without it, cv::dnn, the library's default engine.
engine=()
if python3 -c 'import json, sys
sys.exit(not any(d["name"] == "OpenVINO" for d in json.load(open(sys.argv[1]))))' \
  "$build/meson-info/intro-dependencies.json" 2>/dev/null; then
  engine=(--backend openvino)
fi
echo "demo: jointflow-track ${engine[*]:---backend default (cv::dnn)}, $frames frames of $video" >&2
"$build/apps/jointflow-track" "$video" --max-frames "$frames" "${engine[@]}" \
  --output-video out/vtest-tracked.mp4 --output-json out/vtest.jsonl
