#!/bin/sh
# Runs test_mot_reference.py (jointflow-eval's MOTChallenge box figures against py-motmetrics 1.4.0
# and TrackEval 1.3.0) in a virtual environment with pinned packages, made once in the build folder
# and reused.
# usage: run_mot_reference_check.sh VENV_DIR JOINTFLOW_EVAL [DATA_DIR]
# Exits 77 (meson's "skipped") when the environment cannot be made, e.g. without network.
#
# trackeval 1.3.0 (PyPI, the maintained fork of TrackEval) no longer uses np.float / np.int and
# declares numpy>=2.3.2 and scipy>=1.16.1 for Python 3.11, which motmetrics 1.4.0 and pandas 2.3
# accept too. It is installed without its other declared dependencies (matplotlib, opencv-python,
# pycocotools, pillow: plotting and the mask datasets, about 100 MB) because MotChallenge2DBox and
# the HOTA, CLEAR and Identity metrics import numpy and scipy only.
set -eu
venv=$1
shift
pins="motmetrics==1.4.0 numpy==2.3.5 scipy==1.16.3 pandas==2.3.3 xmltodict==0.13.0"
nodeps="trackeval==1.3.0"
sh "$(dirname "$0")/pinned_venv.sh" "$venv" "$pins" "$nodeps" || exit $?
# JOINTFLOW_DATA in the environment wins over the folder configured at meson setup.
exe=$1
data=${JOINTFLOW_DATA:-${2:-}}
exec "$venv/bin/python" "$(dirname "$0")/test_mot_reference.py" "$exe" "$data"
