#!/usr/bin/env bash
# Installs (once) OpenVINO's C++ runtime for the "openvino" backend: the PyPI wheel `openvino`,
# pinned, into BUILD/venv-openvino. The wheel's include/, libs/ and cmake/ folders are a C++ SDK;
# BUILD/venv-openvino/sdk/openvino points at them (OpenVINO's CMake config finds its libraries
# relative to itself, as site-packages/openvino/cmake/..: the link keeps that layout), and meson
# finds the SDK there (meson.build, option openvino_sdk). The Makefile runs this before
# `meson setup`.
#
# 2026.x wheels are built with the new C++ ABI, as Debian's g++ is (older ones, e.g. 2024.6, use
# the old ABI and do not link). --no-deps: numpy and the telemetry package serve only OpenVINO's
# Python API, which JointFlow does not use.
#   scripts/openvino-venv.sh BUILD
set -euo pipefail
version=2026.4.1
venv="$1/venv-openvino"
stamp="$venv/.jointflow-openvino-$version"
if [ ! -f "$stamp" ]; then
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check --no-deps "openvino==$version"
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  [ -f "$site/openvino/cmake/OpenVINOConfig.cmake" ] || {
    echo "openvino-venv: the wheel has no cmake/OpenVINOConfig.cmake" >&2
    exit 1
  }
  mkdir -p "$venv/sdk"
  ln -sfn "$(realpath --relative-to="$venv/sdk" "$site/openvino")" "$venv/sdk/openvino"
  touch "$stamp"
fi
