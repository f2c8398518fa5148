#!/bin/sh
# An RTSP camera or server with the tracked poses drawn on screen, and the poses of every frame
# printed as JSON Lines on stdout (for a message broker, pipe them on).
#   examples/rtsp.sh rtsp://camera.local:554/stream
# latency=200 bounds the jitter buffer; the leaky queue drops frames rather than letting the
# delay grow when inference is slower than the stream (see docs/gstreamer.md, live sources).
set -eu
uri=${1:?usage: $0 rtsp://HOST[:PORT]/PATH}
export GST_PLUGIN_PATH=${GST_PLUGIN_PATH:-build/gst-plugin}
gst-launch-1.0 -q \
  rtspsrc location="$uri" latency=200 ! decodebin ! videoconvert ! \
  queue leaky=downstream max-size-buffers=1 max-size-bytes=0 max-size-time=0 ! \
  jointflowtrack ! jointflowjsonwriter location=- ! \
  jointflowoverlay ! videoconvert ! autovideosink sync=false
