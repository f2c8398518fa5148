#!/usr/bin/env bash
# The README's "## Python" section as a reader runs it (issue 44): its sh block (a venv, then
# `pip install '.[opencv]'` with build isolation, from the package index) in a copy of the working
# tree, then its python block with that venv's python, which must print poses (lines starting
# with a track id). Both blocks are read from README.md itself and run as written, so the test
# fails when the README's lines stop working. The install compiles the core from scratch (no
# build folder is kept: that is what a reader gets): minutes, hence suite python-wheel
# (`make test-python-wheel`), outside `make test`.
#   test_readme_snippet.sh SOURCE_ROOT
# Exit status: 0, 1 (failed), 77 (meson: SKIP) without vtest.avi, a venv or the package index.
set -euo pipefail
src=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
readme="$src/README.md"
vtest=/usr/share/doc/opencv-doc/examples/data/vtest.avi  # the path the snippet reads

# block LANG: the first ```LANG block of README.md's "## Python" section (headings inside fences
# are code, not headings).
block() {
  awk -v lang="$1" '
    fence && /^```/ { if (want) exit; fence = 0; next }
    fence { if (want) print; next }
    /^```/ { fence = 1; want = section && $0 == "```" lang; next }
    /^## / { section = ($0 == "## Python") }' "$readme"
}
sh_block=$(block sh)
py_block=$(block python)
if [ -z "$sh_block" ] || [ -z "$py_block" ]; then
  echo "FAILED: README.md's \"## Python\" section has no sh block or no python block" >&2
  exit 1
fi
if [ ! -f "$vtest" ]; then
  echo "SKIPPED: $vtest is missing (Debian package opencv-doc), which the snippet reads" >&2
  exit 77
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/jointflow-readme.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# A reader's shell: nothing of meson's test environment or of another venv.
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV JOINTFLOW_MODELS_DIR GST_PLUGIN_PATH GST_REGISTRY
echo "python3: $(command -v python3) ($(python3 --version 2>&1))"

# The install needs the package index (the pinned build requirements, numpy, opencv): without it,
# skip. Probed through a throwaway venv's pip, which reads the same pip configuration.
if ! python3 -m venv "$tmp/probe" >/dev/null 2>&1; then
  echo "SKIPPED: python3 -m venv failed (install python3-venv)" >&2
  exit 77
fi
if ! "$tmp/probe/bin/pip" download --quiet --no-deps --no-cache-dir --disable-pip-version-check \
    -d "$tmp/probe/dl" meson==1.6.1 >/dev/null 2>&1; then
  echo "SKIPPED: the package index cannot be reached (pip download meson==1.6.1 failed)" >&2
  exit 77
fi

# The README runs the sh block in the checkout, where it would leave .venv (and pip's in-tree
# build folder, .mesonpy-*) among the files being edited: a copy of the working tree (tracked and
# untracked-but-not-ignored files, what `pip install .` builds from) takes the checkout's place.
mkdir "$tmp/src"
if git -C "$src" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  git -C "$src" ls-files -z --cached --others --exclude-standard |
    tar -C "$src" --null -T - --ignore-failed-read -cf - | tar -C "$tmp/src" -xf -
else  # an unpacked sdist
  tar -C "$src" --exclude='./build*' --exclude=./.venv -cf - . | tar -C "$tmp/src" -xf -
fi

printf '%s\n' "$sh_block" > "$tmp/readme.sh"
printf '%s\n' "$py_block" > "$tmp/readme.py"
echo "--- sh block:"; cat "$tmp/readme.sh"
start=$(date +%s)
(cd "$tmp/src" && sh -e "$tmp/readme.sh")
installed=$(date +%s)
echo "--- sh block: $((installed - start)) s"

# The wheel carries the licences with the models (Apache 2.0 asks for them to travel together).
for f in LICENSE NOTICE; do
  if ! ls "$tmp"/src/.venv/lib/python3*/site-packages/jointflow-*.dist-info/licenses/$f >/dev/null 2>&1; then
    echo "FAILED: the installed jointflow has no .dist-info/licenses/$f" >&2
    exit 1
  fi
done

# readme.py sits outside the copy, so `import jointflow` finds the installed package only.
(cd "$tmp/src" && .venv/bin/python "$tmp/readme.py") > "$tmp/out.txt"
done_at=$(date +%s)
lines=$(grep -cE '^[0-9]+( |$)' "$tmp/out.txt" || true)
ids=$({ grep -oE '^[0-9]+( |$)' "$tmp/out.txt" || true; } | sort -un | wc -l)
echo "--- python block: $((done_at - installed)) s, $(wc -l < "$tmp/out.txt") lines, $lines pose lines, $ids distinct ids; first and last:"
head -n 3 "$tmp/out.txt"
tail -n 1 "$tmp/out.txt"
if [ "$lines" -lt 1 ]; then
  echo "FAILED: the python block printed no pose line (a line starting with a track id)" >&2
  exit 1
fi
