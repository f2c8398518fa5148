#!/bin/sh
# Runs test_motmetrics.py in a virtual environment with pinned py-motmetrics 1.4.0 (poseval's
# tracking backend) and its numeric stack, made once in the build folder and reused.
# usage: run_motmetrics_check.sh VENV_DIR JOINTFLOW_EVAL [DATA_DIR]
# Exits 77 (meson's "skipped") when the environment cannot be made, e.g. without network.
set -eu
venv=$1
shift
pins="motmetrics==1.4.0 numpy==1.26.4 scipy==1.11.4 pandas==2.1.4 xmltodict==0.13.0"
stamp="$venv/.jointflow-pins"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$pins" ]; then
  rm -rf "$venv"
  if ! python3 -m venv "$venv" >&2; then
    echo "SKIPPED: python3 -m venv failed (install python3-venv)" >&2
    exit 77
  fi
  # shellcheck disable=SC2086  # the pins are separate words on purpose
  if ! "$venv/bin/pip" install --quiet --disable-pip-version-check $pins >&2; then
    echo "SKIPPED: could not install $pins into $venv (no network?)" >&2
    rm -rf "$venv"
    exit 77
  fi
  echo "$pins" > "$stamp"
fi
# JOINTFLOW_DATA in the environment wins over the folder configured at meson setup.
exe=$1
data=${JOINTFLOW_DATA:-${2:-}}
exec "$venv/bin/python" "$(dirname "$0")/test_motmetrics.py" "$exe" "$data"
