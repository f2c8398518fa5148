#!/usr/bin/env bash
# Rewrites the property table of jointflowtrack in docs/gstreamer.md from the element itself
# (build/apps/jointflow-track --properties-markdown). The test plugin-cli checks that it matches.
# usage: scripts/update-property-docs.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
table=$(GST_PLUGIN_PATH="$build/gst-plugin" "$build/apps/jointflow-track" --properties-markdown)
python3 - "$table" <<'PY'
import re, sys
path = "docs/gstreamer.md"
text = open(path, encoding="utf-8").read()
begin = "<!-- properties:jointflowtrack (jointflow-track --properties-markdown) -->\n"
end = "<!-- end properties -->"
a, b = text.index(begin) + len(begin), text.index(end)
open(path, "w", encoding="utf-8").write(text[:a] + sys.argv[1] + "\n" + text[b:])
PY
echo "docs/gstreamer.md: property table updated"
