#!/usr/bin/env bash
# Runs bench/python_overhead.py in BUILD/venv-python (scripts/python-venv.sh) with the module of
# the build folder; meson's benchmark python-overhead (`make bench-python`) calls it.
#   bench/python_overhead.sh BUILD PYTHON [python_overhead.py options]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
python=$(bash "$here/../scripts/python-venv.sh" "$build" "$2")
shift 2
PYTHONPATH="$build/python" exec "$python" "$here/python_overhead.py" "$@"
