#!/bin/sh
# Runs pytest on the given test files in BUILD/venv-python (scripts/python-venv.sh), with the
# module from the build folder first on the path.
#   run_pytest.sh BUILD PYTHON TEST_FILE... [pytest options]
# Exit status: pytest's, 77 (meson: SKIP) when the venv cannot be made or every test skipped.
set -eu
build=$1
python=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
venv_python=$(bash "$here/../../scripts/python-venv.sh" "$build" "$python") || exit $?
export PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONDONTWRITEBYTECODE=1
cd "$here"
exec "$venv_python" -m pytest -p no:cacheprovider -q -rs "$@"
