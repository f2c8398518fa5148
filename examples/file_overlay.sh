#!/bin/sh
# A video file in, the same video with every person's skeleton, id and trail drawn out (MP4),
# plus the poses as JSON Lines. Run from the repository root after `make build`:
#   examples/file_overlay.sh /usr/share/doc/opencv-doc/examples/data/vtest.avi out/overlay.mp4
set -eu
input=${1:?usage: $0 INPUT OUTPUT.mp4 [POSES.jsonl]}
output=${2:?usage: $0 INPUT OUTPUT.mp4 [POSES.jsonl]}
poses=${3:-${output%.*}.jsonl}
export GST_PLUGIN_PATH=${GST_PLUGIN_PATH:-build/gst-plugin}
gst-launch-1.0 -e \
  filesrc location="$input" ! decodebin ! videoconvert ! \
  jointflowtrack similarity=oks ! \
  jointflowjsonwriter location="$poses" ! \
  jointflowoverlay draw-boxes=true ! videoconvert ! video/x-raw,format=I420 ! \
  x264enc speed-preset=veryfast ! mp4mux ! filesink location="$output"
