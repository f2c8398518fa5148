#!/bin/sh
# gst-inspect-1.0 lists the plugin's elements with their properties (GST_PLUGIN_PATH and
# GST_REGISTRY come from the test environment).
set -eu
fail() { echo "inspect: $*" >&2; exit 1; }
out=$(gst-inspect-1.0 jointflow) || fail "plugin jointflow not found in $GST_PLUGIN_PATH"
for element in jointflowtrack jointflowoverlay jointflowjsonwriter jointflowmetapublish; do
  echo "$out" | grep -q "$element" || fail "plugin does not list $element"
done
track=$(gst-inspect-1.0 jointflowtrack) || fail "jointflowtrack not found"
for p in spatial-model model-type tff-model similarity input-size scales max-persons \
         person-threshold keypoint-threshold nms-threshold tau-delta min-track-length \
         lost-time reid joint-threshold min-potential geometric-fallback coast-min-oks duplicate-oks \
         camera-compensation output-tentative smoothing inference-interval backend target \
         num-threads; do
  echo "$track" | grep -qE "^  $p +:" || fail "jointflowtrack has no property $p"
done
overlay=$(gst-inspect-1.0 jointflowoverlay) || fail "jointflowoverlay not found"
for p in draw-boxes draw-ids trail-length thickness keypoint-threshold; do
  echo "$overlay" | grep -qE "^  $p +:" || fail "jointflowoverlay has no property $p"
done
for f in RGB BGR RGBx BGRx xRGB xBGR RGBA BGRA I420 NV12; do
  echo "$track" | grep -q "(string)$f[,} ]" || fail "jointflowtrack caps lack $f"
done
publish=$(gst-inspect-1.0 jointflowmetapublish) || fail "jointflowmetapublish not found"
for p in method address topic client-id source-id config-file max-connect-attempts \
         max-reconnect-interval connect-timeout max-queue-size max-message-size flush-timeout \
         messages-published messages-dropped messages-refused queue-depth; do
  echo "$publish" | grep -qE "^  $p *:" || fail "jointflowmetapublish has no property $p"
done
for m in file mqtt kafka; do
  echo "$publish" | grep -qE "\(.\): $m " || fail "jointflowmetapublish method lacks $m"
done
writer=$(gst-inspect-1.0 jointflowjsonwriter) || fail "jointflowjsonwriter not found"
echo "$writer" | grep -qE "^  source-id +:" || fail "jointflowjsonwriter has no property source-id"
echo "inspect: ok"
