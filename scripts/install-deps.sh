#!/usr/bin/env bash
# Installs the Debian bookworm packages JointFlow builds, tests and demos with.
# Idempotent: packages already present are skipped, so `make` targets can call it every time.
# Runs as root, or through sudo where that is available.
set -euo pipefail

PACKAGES=(
  build-essential pkg-config meson ninja-build cmake clang-format ccache
  libopencv-dev opencv-doc libeigen3-dev catch2 nlohmann-json3-dev libcli11-dev
  libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev libgstreamer-plugins-bad1.0-dev
  gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good
  gstreamer1.0-plugins-bad gstreamer1.0-plugins-ugly gstreamer1.0-libav
  python3 python3-venv
  libmosquitto-dev librdkafka-dev mosquitto mosquitto-clients openssl
  # The RTSP camera of the tests (tests/rtsp): gst-rtsp-server serving H.264 from x264enc
  # (plugins-ugly); the client decodes with avdec_h264 (gstreamer1.0-libav).
  libgstrtspserver-1.0-dev
  # jointflow-track --metrics-port: the HTTP server of /metrics.
  libmicrohttpd-dev
  maven openjdk-17-jre-headless
  # The Python module (python/): headers, pybind11, numpy; jointflow.gst reads buffers through
  # PyGObject (python-gi-dev for the build, python3-gi and GStreamer's typelibs to run);
  # python3-opencv for the examples and tests (Debian's OpenCV 4.6, the same as the core's).
  python3-dev pybind11-dev python3-numpy python-gi-dev python3-gi python3-gst-1.0
  gir1.2-gstreamer-1.0 gir1.2-gst-plugins-base-1.0 python3-opencv
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
