#!/usr/bin/env bash
# `make demo`: pose estimation on frames of vtest.avi (ships with Debian's opencv-doc), annotated
# images under out/. Replaced by the tracking demo once the plugin and command line exist.
set -euo pipefail
build=${1:-build}
video=${JOINTFLOW_VTEST:-/usr/share/doc/opencv-doc/examples/data/vtest.avi}
mkdir -p out
"$build/examples/demo_frames" "$video" out
