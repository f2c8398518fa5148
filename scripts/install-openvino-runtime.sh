#!/usr/bin/env bash
# `meson install` step (core/meson.build): copies OpenVINO's runtime, the SDK's libs/ folder (the
# libraries, the device plugins OpenVINO finds beside libopenvino.so, TBB), into the install, where
# the installed libjointflow-openvino.so finds it by its rpath $ORIGIN/jointflow/openvino, and the
# wheel's licence files beside the documents (OpenVINO and TBB are Apache-2.0; the
# third-party-programs files list what they contain).
#   install-openvino-runtime.sh SDK LIB_DIR LICENCE_DIR    (dirs relative to the prefix, or absolute)
set -euo pipefail
sdk="$1"
# Meson gives the prefix with DESTDIR applied; an absolute folder (outside the prefix) gets DESTDIR.
dest() { case "$1" in /*) echo "${DESTDIR:-}$1" ;; *) echo "$MESON_INSTALL_DESTDIR_PREFIX/$1" ;; esac; }
libs="$(dest "$2")"
licences="$(dest "$3")"
[ -d "$sdk/libs" ] || { echo "install-openvino-runtime: $sdk/libs is missing" >&2; exit 1; }
echo "Installing OpenVINO's runtime $sdk/libs to $libs"
rm -rf "$libs"
mkdir -p "$libs" "$licences"
cp -RL "$sdk/libs/." "$libs/"
# The wheel's licences sit in its .dist-info folder beside the package (sdk links to the package).
dist_info=("$(cd -P "$sdk" && pwd)"/../openvino-*.dist-info/licenses)
if [ -d "${dist_info[0]}" ]; then
  cp -RL "${dist_info[0]}/." "$licences/"
else
  echo "install-openvino-runtime: warning: no licence files beside $sdk (${dist_info[0]})" >&2
fi
