#!/usr/bin/env bash
# Makes (once) the Python environment of the benchmarks in BUILD/venv-bench: onnxruntime for the
# cv::dnn comparison, matplotlib for the soak plot. Pinned; prints the venv's python.
#   bench/venv.sh BUILD
set -euo pipefail
venv="$1/venv-bench"
stamp="$venv/.jointflow-bench-1"
if [ ! -f "$stamp" ]; then
  python3 -m venv "$venv" >&2
  "$venv/bin/pip" install -q onnxruntime==1.26.0 numpy==1.26.4 matplotlib==3.9.2 >&2
  touch "$stamp"
fi
echo "$venv/bin/python"
