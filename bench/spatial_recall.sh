#!/usr/bin/env bash
# `make bench-spatial`: how many of the people a camera shows each spatial option finds.
# For every option below, jointflow-track tracks each MOT17-mini sequence (--output-mot) and
# jointflow-eval --mot-gt scores it (recall, precision, MOTA, IDF1, HOTA per scene); the public
# Faster R-CNN detections shipped with MOT17 (det/det.txt, score >= 0.5) are scored beside them.
# Each option also tracks vtest.avi (768x576, 795 frames) headless, timed as a whole process.
# Writes docs/spatial-recall.md and docs/spatial-recall.json.
#   bench/spatial_recall.sh [BUILD [DATA_DIR [--option "name|jointflow-track options"]...]]
# DATA_DIR (default ../shared/data, or $JOINTFLOW_DATA) must hold mot17-mini/train; each --option
# adds a spatial option to the ones below.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
DATA=${2:-${JOINTFLOW_DATA:-../shared/data}}
shift 2 || shift $#
MOT="$DATA/mot17-mini/train"
VTEST=/usr/share/doc/opencv-doc/examples/data/vtest.avi
if [ ! -d "$MOT" ]; then
  echo "bench-spatial: no $MOT (give the data folder as the second argument)" >&2
  exit 1
fi
ninja -C "$BUILD" apps/jointflow-track apps/jointflow-eval gst-plugin/libgstjointflow.so
export GST_PLUGIN_PATH="$PWD/$BUILD/gst-plugin" GST_REGISTRY="$PWD/$BUILD/bench/gst-registry.bin"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# name | jointflow-track options (the engine is OpenVINO throughout: the issue's measure)
OPTIONS=(
  "default (tiles of 640 + the whole frame at max:640)|--backend openvino"
  "whole frame only, max:640 (the default before 7 December 2026)|--backend openvino --tiles false"
  "native input, whole frame only|--backend openvino --input-size native --tiles false"
  "tiles of 512 + the whole frame|--backend openvino --tile-size 512"
  "scales 1,2 (no tiles)|--backend openvino --scales 1,2"
)
while [ $# -gt 0 ]; do
  case $1 in
    --option) OPTIONS+=("$2"); shift 2 ;;
    *) echo "bench-spatial: unknown argument $1" >&2; exit 2 ;;
  esac
done

results="$OUT/results.jsonl"
load_before=$(cut -d' ' -f1 /proc/loadavg)
for entry in "${OPTIONS[@]}"; do
  name=${entry%%|*}
  args=${entry#*|}
  dir="$OUT/pred-$(echo "$name" | tr -c 'a-zA-Z0-9' '_')"
  mkdir -p "$dir"
  echo "bench-spatial: $name" >&2
  for seq in "$MOT"/*/; do
    seq=$(basename "$seq")
    # shellcheck disable=SC2086  # the options are separate words on purpose
    "$BUILD/apps/jointflow-track" "$MOT/$seq/img1" $args -q --output-mot "$dir/$seq.txt"
  done
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  "$BUILD/apps/jointflow-track" "$VTEST" $args -q --output-json "$OUT/vtest.jsonl"
  end=$(date +%s.%N)
  frames=$(wc -l < "$OUT/vtest.jsonl")
  "$BUILD/apps/jointflow-eval" --mot-gt "$MOT" --pred "$dir" --json > "$OUT/eval.json"
  python3 -c 'import json,sys; print(json.dumps({"name": sys.argv[1], "args": sys.argv[2],
    "vtest_fps": int(sys.argv[3]) / (float(sys.argv[5]) - float(sys.argv[4])),
    "scores": json.load(open(sys.argv[6]))}))' \
    "$name" "$args" "$frames" "$start" "$end" "$OUT/eval.json" >> "$results"
done
mkdir -p "$OUT/frcnn"
for seq in "$MOT"/*/; do cp "$seq/det/det.txt" "$OUT/frcnn/$(basename "$seq").txt"; done
"$BUILD/apps/jointflow-eval" --mot-gt "$MOT" --pred "$OUT/frcnn" --min-score 0.5 --json \
  > "$OUT/frcnn.json"
# The frames/s move with the machine's load: the table says what it was.
LOAD="$load_before to $(cut -d' ' -f1 /proc/loadavg)" \
  python3 bench/spatial_recall_table.py "$results" "$OUT/frcnn.json" docs/spatial-recall.md \
  docs/spatial-recall.json
cat docs/spatial-recall.md
