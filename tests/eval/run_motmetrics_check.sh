#!/bin/sh
# Runs test_motmetrics.py in a virtual environment with pinned py-motmetrics 1.4.0 (poseval's
# tracking backend) and its numeric stack, made once in the build folder and reused.
# usage: run_motmetrics_check.sh VENV_DIR JOINTFLOW_EVAL [DATA_DIR]
# Exits 77 (meson's "skipped") when the environment cannot be made, e.g. without network.
set -eu
venv=$1
shift
pins="motmetrics==1.4.0 numpy==1.26.4 scipy==1.11.4 pandas==2.1.4 xmltodict==0.13.0"
sh "$(dirname "$0")/pinned_venv.sh" "$venv" "$pins" || exit $?
# JOINTFLOW_DATA in the environment wins over the folder configured at meson setup.
exe=$1
data=${JOINTFLOW_DATA:-${2:-}}
exec "$venv/bin/python" "$(dirname "$0")/test_motmetrics.py" "$exe" "$data"
