#!/usr/bin/env bash
# `make bench`: builds the benchmarks, makes their Python environment (onnxruntime) once, and runs
# jointflow-bench, which prints its tables and writes docs/benchmarks.md.
#   bench/run.sh [BUILD] [extra jointflow-bench options]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
shift || true
ninja -C "$BUILD" bench/jointflow-bench gst-plugin/libgstjointflow.so
python=$(bash bench/venv.sh "$BUILD")
GST_PLUGIN_PATH="$PWD/$BUILD/gst-plugin" GST_REGISTRY="$PWD/$BUILD/bench/gst-registry.bin" \
  "$BUILD/bench/jointflow-bench" --python "$python" --ort-script bench/ort_time.py \
  --out docs/benchmarks.md "$@"
