#!/usr/bin/env bash
# Makes (once) the Python environment of the module's tests and bench in BUILD/venv-python, with
# the Python the module was built for (PYTHON: meson's, Debian's /usr/bin/python3) and its
# system site-packages, where Debian's gi (python3-gi, for jointflow.gst) and cv2
# (python3-opencv) are; pinned pytest, numpy and meson-python (the wheel test builds with it,
# without build isolation, on Debian's meson, ninja and pybind11). Prints the venv's python.
# Exits 77 (meson: SKIP) when the environment cannot be made, e.g. without the registry.
#   scripts/python-venv.sh BUILD PYTHON
set -euo pipefail
venv="$1/venv-python"
python=${2:-python3}
# --no-deps with every package named: the same set everywhere, whatever the system has.
pins="pytest==8.3.4 pluggy==1.5.0 iniconfig==2.0.0 packaging==24.2 numpy==1.26.4
meson-python==0.18.0 pyproject-metadata==0.9.1"
stamp="$venv/.jointflow-pins"
# The python and python-gst suites run side by side and both come here: one makes the venv while
# the other waits, then finds it made. Without the lock the second removed the first's half-made
# venv, and its ensurepip failed (the suite said SKIP on a fresh clone).
mkdir -p "$1"
exec 9>"$1/venv-python.lock"
flock 9
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$pins $python" ]; then
  rm -rf "$venv"
  if ! "$python" -m venv --system-site-packages "$venv" >&2; then
    echo "SKIPPED: $python -m venv failed (install python3-venv)" >&2
    exit 77
  fi
  # shellcheck disable=SC2086  # the pins are separate words on purpose
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps $pins >&2; then
    echo "SKIPPED: could not install $pins into $venv (no registry?)" >&2
    rm -rf "$venv"
    exit 77
  fi
  echo "$pins $python" > "$stamp"
fi
echo "$venv/bin/python"
