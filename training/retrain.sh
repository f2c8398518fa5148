#!/usr/bin/env bash
# Retrains the shipped TFF network (models/tff_movenet.onnx) with one command: `make train-tff`.
#
#   1. training/setup.sh: the pinned venv (training/.venv);
#   2. precompute.py: MoveNet once over the training videos at the run-time policy max:640, 72
#      frames each, plain + mirrored, 72 camera-motion warps each (cached in training/.cache/maps;
#      a video already there is skipped);
#   3. train.py with the shipped settings (its defaults) -> training/runs/retrain/{tff.onnx, loss.png, log.csv, summary.json};
#   4. evaluate.py: the held-out videos, the new network against the shipped one and the baselines;
#   5. measure_cost.py: TFF against MoveNet at 256x256, max:640 and the Bonn frames' native size.
# It does not overwrite models/tff_movenet.onnx: ship by hand after reading the figures
# (models/README.md, "tff_movenet.onnx"), then update models/SHA256SUMS.
#
# Environment: JOBS (precompute processes, default 2), THREADS (torch/onnxruntime threads, 2),
# OUT (run folder), NICE (niceness, 10: this shares the machine with builds).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
py="$here/.venv/bin/python"
out="${OUT:-$here/runs/retrain}"
run() { nice -n "${NICE:-10}" "$@"; }

"$here/setup.sh"
threads="${THREADS:-2}"
jobs="${JOBS:-2}"
run "$py" "$here/precompute.py" --jobs "$jobs" --threads $(( threads / jobs > 0 ? threads / jobs : 1 ))
run "$py" "$here/train.py" --out "$out" --threads "$threads"
run "$py" "$here/evaluate.py" "shipped=$root/models/tff_movenet.onnx" "retrained=$out/tff.onnx" \
  --json "$out/evaluate.json" | tee "$out/evaluate.txt"
run "$py" "$here/measure_cost.py" "$out/tff.onnx" --threads "$threads" | tee "$out/cost.txt"
echo "retrained: $out/tff.onnx (loss curves $out/loss.png); to ship: cp $out/tff.onnx $root/models/tff_movenet.onnx"
