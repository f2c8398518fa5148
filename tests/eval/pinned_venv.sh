#!/bin/sh
# Makes (once) a virtual environment with pinned packages for a reference check, reused while
# the pins stay the same (a stamp file in it names them).
# usage: pinned_venv.sh VENV_DIR "PINS" ["PINS INSTALLED WITHOUT THEIR DEPENDENCIES"]
# Exits 77 (meson's "skipped") when the environment cannot be made, e.g. without network.
set -eu
venv=$1
pins=$2
nodeps=${3:-}
want=$(echo "$pins $nodeps" | sed 's/ *$//')
stamp="$venv/.jointflow-pins"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
rm -rf "$venv"
if ! python3 -m venv "$venv" >&2; then
  echo "SKIPPED: python3 -m venv failed (install python3-venv)" >&2
  exit 77
fi
# shellcheck disable=SC2086  # the pins are separate words on purpose
if ! "$venv/bin/pip" install --quiet --disable-pip-version-check $pins >&2 ||
   { [ -n "$nodeps" ] &&
     ! "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps $nodeps >&2; }; then
  echo "SKIPPED: could not install $want into $venv (no network?)" >&2
  rm -rf "$venv"
  exit 77
fi
echo "$want" > "$stamp"
