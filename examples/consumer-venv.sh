#!/usr/bin/env bash
# Makes (once) the Python environment of examples/consumer.py in BUILD/venv-consumer, with the
# pinned clients it imports; prints the venv's python. Used by the publish tests.
#   examples/consumer-venv.sh BUILD
set -euo pipefail
venv="$(mkdir -p "$1" && cd "$1" && pwd)/venv-consumer"
stamp="$venv/.jointflow-consumer-1"
if [ ! -f "$stamp" ]; then
  rm -rf "$venv"
  python3 -m venv "$venv" >&2
  "$venv/bin/pip" install -q confluent-kafka==2.16.1 paho-mqtt==2.2.0 >&2
  touch "$stamp"
fi
echo "$venv/bin/python"
