#!/usr/bin/env bash
# `make soak`: long runs of jointflowtrack (bench/soak.cpp), not part of `make test`.
#   1. Leaks: SOAK_LEAK_FRAMES (2000) frames through the element built with AddressSanitizer and
#      LeakSanitizer (build-asan, as `make test-asan` makes it); any leak fails the run.
#   2. Memory over time: SOAK_FRAMES (10000) frames through the release build, resident memory
#      every 100 frames -> docs/soak-rss.csv, plotted to docs/soak-rss.png.
#   bench/soak.sh [BUILD] [ASAN_BUILD]        (SOAK_FRAMES=0: the leak check only)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ASAN_BUILD=${2:-build-asan}
LEAK_FRAMES=${SOAK_LEAK_FRAMES:-2000}
FRAMES=${SOAK_FRAMES:-10000}
WIDTH=${SOAK_WIDTH:-192}

echo "soak: $LEAK_FRAMES frames under LeakSanitizer ($ASAN_BUILD)"
[ -f "$ASAN_BUILD/build.ninja" ] || meson setup "$ASAN_BUILD" --buildtype=debugoptimized \
  -Db_sanitize=address,undefined -Db_lundef=false -Dpython=disabled
ninja -C "$ASAN_BUILD" bench/soak gst-plugin/libgstjointflow.so
ASAN_OPTIONS=detect_leaks=1:fast_unwind_on_malloc=0:malloc_context_size=60 \
  LSAN_OPTIONS=suppressions=$PWD/tests/hardening/lsan.supp \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 G_SLICE=always-malloc GST_REGISTRY_FORK=no \
  GST_PLUGIN_PATH="$PWD/$ASAN_BUILD/gst-plugin" GST_REGISTRY="$PWD/$ASAN_BUILD/bench/registry.bin" \
  "$ASAN_BUILD/bench/soak" --frames "$LEAK_FRAMES" --every 500 --width "$WIDTH" \
  --csv "$ASAN_BUILD/soak-asan-rss.csv"
echo "soak: no leak in $LEAK_FRAMES frames"

[ "$FRAMES" -gt 0 ] || exit 0
echo "soak: $FRAMES frames, resident memory every 100 ($BUILD)"
ninja -C "$BUILD" bench/soak gst-plugin/libgstjointflow.so
GST_PLUGIN_PATH="$PWD/$BUILD/gst-plugin" GST_REGISTRY="$PWD/$BUILD/bench/registry.bin" \
  "$BUILD/bench/soak" --frames "$FRAMES" --every 100 --width "$WIDTH" --csv docs/soak-rss.csv
python=$(bash bench/venv.sh "$BUILD")
"$python" bench/plot_rss.py docs/soak-rss.csv docs/soak-rss.png \
  "jointflowtrack, $FRAMES frames of vtest.avi at ${WIDTH} px wide: resident memory"
echo "soak: docs/soak-rss.png"
