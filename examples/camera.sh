#!/bin/sh
# A live camera (V4L2) with the tracked poses drawn on screen.
#   examples/camera.sh [/dev/video0]
# Live policy: the leaky queue keeps only the newest frame while jointflowtrack is busy, so the
# delay stays one inference long however slow the CPU is; jointflowtrack additionally predicts
# (instead of infers) the frames the display reports as late (skip-late-frames, on by default).
# inference-interval=2 halves the network load; the frames in between are predicted from each
# track's velocity, so they neither freeze nor flicker.
set -eu
device=${1:-/dev/video0}
export GST_PLUGIN_PATH=${GST_PLUGIN_PATH:-build/gst-plugin}
gst-launch-1.0 \
  v4l2src device="$device" ! videoconvert ! \
  queue leaky=downstream max-size-buffers=1 max-size-bytes=0 max-size-time=0 ! \
  jointflowtrack inference-interval=2 input-size=max:480 ! \
  jointflowoverlay ! videoconvert ! autovideosink sync=true
