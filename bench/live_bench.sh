#!/usr/bin/env bash
# The live RTSP benchmarks of issue 43, not part of `make test`: jointflow-track on the tests'
# camera (jointflow-rtsp-test-server: vtest.avi looped as live H.264), watched from outside by
# bench/live_run.py.
#   latency (`make bench-latency`): a 30 frames/s camera, faster than the tracker (cv::dnn by
#     default), for 10 minutes; each frame's lag from capture to poses (--output-lag)
#     -> docs/latency.md ("This run"), docs/latency.png, docs/latency.csv.
#   soak (`make soak-live`): an hour at the camera's own 10 frames/s, the camera killed and started
#     again every 10 minutes, alternately for 3 s and 30 s; resident memory, threads and open
#     file descriptors from /proc every 10 s -> docs/soak-live.md, .png, .csv.
#
#   bench/live_bench.sh latency|soak [BUILD] [--duration S] [--outage-every S] [-- track options]
# A short run (--duration 60) tries the tool; it rewrites the docs' figures all the same, so do
# not commit it.
set -euo pipefail
cd "$(dirname "$0")/.."
MODE=${1:?usage: bench/live_bench.sh latency|soak [BUILD] [--duration S] [--outage-every S]}
shift
BUILD=build
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then BUILD=$1; shift; fi
case "$MODE" in
  latency) DURATION=600; OUTAGE_EVERY=0 ;;
  soak) DURATION=3600; OUTAGE_EVERY=600 ;;
  *) echo "live_bench.sh: mode latency or soak, not $MODE" >&2; exit 2 ;;
esac
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) DURATION=$2; shift 2 ;;
    --outage-every) OUTAGE_EVERY=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "live_bench.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
out="$BUILD/live-$MODE"
ninja -C "$BUILD" apps/jointflow-track tests/rtsp/jointflow-rtsp-test-server \
  gst-plugin/libgstjointflow.so
echo "live $MODE: $DURATION s; load: $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$MODE" = latency ]; then
  run=(--fps 30 --lag)
else
  run=(--outage-every "$OUTAGE_EVERY" --outage-lengths 3,30)
fi
status=0
python3 bench/live_run.py --build "$BUILD" --duration "$DURATION" --out "$out" \
  --sample-every 10 "${run[@]}" -- "$@" || status=$?
[ "$status" -eq 77 ] && exit 77
command="bench/live_bench.sh $MODE $BUILD --duration $DURATION"
[ "$MODE" = soak ] && command+=" --outage-every $OUTAGE_EVERY"
[ $# -gt 0 ] && command+=" -- $*"
python=$(bash bench/venv.sh "$BUILD")
if [ "$MODE" = latency ]; then
  "$python" bench/latency_report.py "$out" docs/latency.png docs/latency.md docs/latency.csv \
    "$command"
else
  cp "$out/samples.csv" docs/soak-live.csv
  "$python" bench/soak_live_report.py "$out" docs/soak-live.png docs/soak-live.md "$command"
fi
exit "$status"
