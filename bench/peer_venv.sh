#!/usr/bin/env bash
# Makes (once) the venv of one peer tracker for bench/peer_trackers.py in BUILD/venv-peer-NAME,
# from bench/peers/NAME.txt (pinned; the two need different numpy majors, hence two venvs), and
# prints its python.
#   bench/peer_venv.sh BUILD bytetrack|norfair
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
requirements="$here/peers/$2.txt"
[ -f "$requirements" ] || { echo "peer_venv.sh: no $requirements" >&2; exit 2; }
venv="$1/venv-peer-$2"
stamp="$venv/.jointflow-$(sha256sum "$requirements" | cut -c1-12)"
if [ ! -f "$stamp" ]; then
  rm -rf "$venv"
  python3 -m venv "$venv" >&2
  "$venv/bin/pip" install -q --no-deps -r "$requirements" >&2
  touch "$stamp"
fi
echo "$venv/bin/python"
