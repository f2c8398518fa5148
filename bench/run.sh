#!/usr/bin/env bash
# `make bench`: builds the benchmarks, makes their Python environment (onnxruntime) once, and runs
# jointflow-bench, which prints its tables and writes docs/benchmarks.md, then identity-bench
# (docs/identity.md, docs/identity.json, plotted to docs/identity.png), crossing-bench
# (docs/crossings.md) and the labelled vtest.avi check (bench/vtest_identity.py:
# docs/identity-vtest.md, .json). `make bench-identity` runs the last three only.
#   bench/run.sh [BUILD] [--identity-only | extra jointflow-bench options]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
shift || true
export GST_PLUGIN_PATH="$PWD/$BUILD/gst-plugin" GST_REGISTRY="$PWD/$BUILD/bench/gst-registry.bin"
if [ "${1:-}" = "--identity-only" ]; then
  ninja -C "$BUILD" bench/identity-bench bench/crossing-bench gst-plugin/libgstjointflow.so \
    apps/jointflow-track apps/jointflow-eval
else
  ninja -C "$BUILD" bench/jointflow-bench bench/identity-bench bench/crossing-bench \
    gst-plugin/libgstjointflow.so apps/jointflow-track apps/jointflow-eval
  python=$(bash bench/venv.sh "$BUILD")
  "$BUILD/bench/jointflow-bench" --python "$python" --ort-script bench/ort_time.py \
    --out docs/benchmarks.md "$@"
fi
"$BUILD/bench/identity-bench" --out docs/identity.md --json docs/identity.json \
  --vtest-sheet docs/identity-vtest.jpg
# The same figures as a picture (docs/identity.png, shown in docs/tracking.md).
"$(bash bench/venv.sh "$BUILD")" bench/plot_identity.py docs/identity.json docs/identity.png
# Two people crossing or meeting, with real articulation (bench/crossings.hpp).
"$BUILD/bench/crossing-bench" --pairs 300 --out docs/crossings.md
# Identity against our own labels of vtest.avi (tests/data/vtest-identity), every similarity with
# re-entry on and off.
python3 bench/vtest_identity.py "$BUILD"
