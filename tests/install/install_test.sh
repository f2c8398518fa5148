#!/usr/bin/env bash
# The install as a user gets it (docs/deploy.md): `meson install` of this build into a temporary
# folder, the prefix then moved elsewhere, and the source and build trees hidden (a mount
# namespace with an empty tmpfs over each: the compiled-in source path then points nowhere, as
# after a deleted source tree or under a unit's ProtectHome=). From there:
#   - the installed jointflow-track tracks 5 frames of vtest.avi, with the models of the moved
#     prefix (the log names the file) and finds people; with OpenVINO where the build has it;
#   - gst-inspect-1.0 jointflowtrack and a gst-launch-1.0 pipeline of 5 frames, with
#     GST_PLUGIN_PATH on the installed plugin, find people;
#   - the installed Python module loads the models;
#   - without the models folder the error lists every folder looked in;
# and the files the systemd units name (ExecStart=, Documentation=, GST_PLUGIN_PATH) exist in the
# install, the models match their SHA256SUMS, the documents and licences are there.
#   install_test.sh BUILD_ROOT SOURCE_ROOT PREFIX BINDIR LIBDIR DATADIR PYTHON PY_INSTALL_DIR VTEST OPENVINO
set -euo pipefail
build=$1 source=$2 prefix=$3 bindir=$4 libdir=$5 datadir=$6 python=$7 py_dir=$8 vtest=$9
openvino=${10}
fail() { echo "install: FAIL: $*" >&2; exit 1; }
step() { echo "install: $*"; }
start=$(date +%s.%N)
elapsed() { python3 -c "import sys, time; print(f'{time.time() - float(sys.argv[1]):.1f} s')" "$start"; }
[ -f "$vtest" ] || { echo "install: $vtest is missing (Debian's opencv-doc)"; exit 77; }

# The temporary folder must lie outside both trees, which are hidden below.
tmp=$(mktemp -d "${TMPDIR:-/tmp}/jointflow-install.XXXXXX")
case "$tmp/" in "$source/"* | "$build/"*) rm -rf "$tmp"; tmp=$(mktemp -d /tmp/jointflow-install.XXXXXX) ;; esac
trap 'rm -rf "$tmp"' EXIT
trap 'exit 1' INT TERM  # meson's timeout: the EXIT trap still removes the copies (200 MB)
tmp=$(cd "$tmp" && pwd -P)  # as the programs see their own paths: links resolved

meson install -C "$build" --no-rebuild --destdir "$tmp/destdir" >"$tmp/install.log" 2>&1 ||
  { tail -20 "$tmp/install.log" >&2; fail "meson install failed"; }
# Moved: the installed files must find each other relative to themselves, not by the prefix.
under() { case "$1" in /*) echo "$2$1" ;; *) echo "$2$prefix/$1" ;; esac; }
moved=$tmp/moved
mv "$(under "$prefix" "$tmp/destdir")" "$moved"
outside=$(find "$tmp/destdir" -type f | head -3)
[ -z "$outside" ] || step "note: installed outside the prefix (not moved): $outside"
step "installed and moved to $moved ($(elapsed))"

rel() { case "$1" in /*) fail "$1 is outside the prefix: this test needs it inside" ;; *) echo "$1" ;; esac; }
models=$moved/$(rel "$datadir")/jointflow/models
docs=$moved/$(rel "$datadir")/doc/jointflow
plugins=$moved/$(rel "$libdir")/gstreamer-1.0
exe=$moved/$(rel "$bindir")/jointflow-track
for f in movenet_multipose.onnx posenet_mobilenetv1.onnx tff_movenet.onnx SHA256SUMS README.md; do
  [ -f "$models/$f" ] || fail "$models/$f was not installed"
done
(cd "$models" && sha256sum --quiet -c SHA256SUMS) || fail "the installed models differ from SHA256SUMS"
for f in README.md LICENSE NOTICE docs/deploy.md docs/gstreamer.md; do
  [ -f "$docs/$f" ] || fail "$docs/$f was not installed"
done
[ -x "$exe" ] || fail "$exe was not installed"
[ -f "$plugins/libgstjointflow.so" ] || fail "$plugins/libgstjointflow.so was not installed"

# The units name /usr/local paths: each must be a file the install of prefix /usr/local creates.
if [ "$prefix" = /usr/local ]; then
  for unit in "$source"/deploy/systemd/*.service; do
    sed -nE 's|^ExecStart=(/usr/local/[^ ]+).*|\1|p; s|^Documentation=file://(/usr/local/[^ ]+).*|\1|p;
             s|^Environment=GST_PLUGIN_PATH=(/usr/local/[^ ]+).*|\1|p' "$unit" >"$tmp/named"
    while read -r path; do
      [ -e "$moved${path#/usr/local}" ] || fail "$(basename "$unit") names $path, which the install lacks"
    done <"$tmp/named"
  done
  grep -q . "$tmp/named" || fail "found no /usr/local path in the units"
else
  step "prefix $prefix is not /usr/local: the units' paths are not checked"
fi

# The runs below, in a mount namespace where the source and build trees are empty folders.
cat >"$tmp/runs.sh" <<'EOF'
set -euo pipefail
fail() { echo "install: FAIL: $*" >&2; exit 1; }
step() { echo "install: [${SECONDS} s] $*"; }
cd "$TMP"  # not in a tree about to be hidden
# The build folder first: it may lie inside the source tree.
if [ -n "$HIDE" ]; then
  for tree in "$BUILD" "$SOURCE"; do
    [ -d "$tree" ] || continue
    mount -t tmpfs -o size=1m jointflow-hidden "$tree"
  done
  for tree in "$BUILD" "$SOURCE"; do
    [ ! -e "$tree" ] || [ -z "$(ls -A "$tree")" ] || fail "$tree is still visible"
  done
  step "the source tree $SOURCE and the build folder $BUILD are hidden"
fi
unset JOINTFLOW_MODELS_DIR GST_PLUGIN_PATH LD_LIBRARY_PATH PYTHONPATH JOINTFLOW_OPENVINO_MODULE
export GST_REGISTRY=$TMP/registry.bin GST_DEBUG_NO_COLOR=1
# people FILE: the largest number of people in a frame of a JSON Lines file (5 lines expected).
people() {
  "$PYTHON" - "$1" <<'PY'
import json, sys
frames = [json.loads(line) for line in open(sys.argv[1])]
assert len(frames) == 5, f"{len(frames)} frames, not 5"
print(max(len(f["objects"]) for f in frames))
PY
}
track() {  # LABEL ARGS...: jointflow-track on 5 frames; people found, models of the install
  local label=$1
  shift
  GST_DEBUG=jointflowtrack:4 "$EXE" "$VTEST" --max-frames 5 --quiet --output-json "$TMP/$label.jsonl" \
    "$@" 2>"$TMP/$label.log" || { tail -5 "$TMP/$label.log" >&2; fail "jointflow-track $* failed"; }
  grep -q "from $MODELS/movenet_multipose.onnx" "$TMP/$label.log" ||
    fail "jointflow-track $* did not load $MODELS/movenet_multipose.onnx: $(grep -o 'models loaded.*' "$TMP/$label.log")"
  n=$(people "$TMP/$label.jsonl")
  [ "$n" -ge 2 ] || fail "jointflow-track $*: at most $n people in a frame of vtest.avi"
  step "jointflow-track ($label): up to $n people a frame; $(grep -o 'models loaded.*' "$TMP/$label.log" | head -1)"
}
track cv-dnn
if [ "$OPENVINO" = yes ]; then
  track openvino --backend openvino
fi

out=$(GST_PLUGIN_PATH=$PLUGINS gst-inspect-1.0 jointflowtrack) || fail "gst-inspect-1.0 jointflowtrack failed"
echo "$out" | grep -q "$PLUGINS/libgstjointflow.so" || fail "gst-inspect-1.0 found another plugin"
GST_PLUGIN_PATH=$PLUGINS gst-launch-1.0 -q filesrc location="$VTEST" ! decodebin ! videoconvert ! \
  identity eos-after=5 ! jointflowtrack ! jointflowjsonwriter location="$TMP/launch.jsonl" ! \
  fakesink >"$TMP/launch.log" 2>&1 || { tail -5 "$TMP/launch.log" >&2; fail "gst-launch-1.0 failed"; }
n=$(people "$TMP/launch.jsonl")
[ "$n" -ge 2 ] || fail "gst-launch-1.0: at most $n people in a frame of vtest.avi"
step "gst-inspect-1.0 jointflowtrack and gst-launch-1.0 with GST_PLUGIN_PATH=$PLUGINS: up to $n people a frame"

if [ -n "$PYDIR" ] && [ -f "$PYDIR/jointflow/__init__.py" ]; then
  PYTHONPATH=$PYDIR "$PYTHON" -c '
import sys, jointflow
assert jointflow.__file__.startswith(sys.argv[1]), jointflow.__file__
jointflow.Tracker(similarity="tff")  # loads MoveNet and the TFF network' "$PYDIR" ||
    fail "the Python module failed"
  step "the installed Python module ($PYDIR) loads the models"
fi

# Without the models: the error names every folder looked in.
mv "$MODELS" "$MODELS.away"
if "$EXE" "$VTEST" --max-frames 1 --quiet 2>"$TMP/missing.log"; then fail "ran without the models"; fi
mv "$MODELS.away" "$MODELS"
for want in "Could not load the JointFlow models" "no models folder has movenet_multipose.onnx" \
            "$MODELS (installed with " "$SOURCE/models (the source tree"; do
  grep -qF "$want" "$TMP/missing.log" || fail "the error without models lacks \"$want\": $(cat "$TMP/missing.log")"
done
step "without the models: $(grep -o 'no models folder.*' "$TMP/missing.log" | head -1)"
EOF

# The Python package's folder in the moved prefix, where it was installed inside the prefix.
case "$py_dir" in "$prefix"/*) pydir=$moved/${py_dir#"$prefix"/} ;; *) pydir= ;; esac
# A mount namespace: as root, else as a user namespace's root where the kernel allows it.
hide=yes namespace=(unshare -m --propagation private)
if ! "${namespace[@]}" true 2>/dev/null; then
  namespace=(unshare -r -m --propagation private)
  "${namespace[@]}" true 2>/dev/null || {
    hide= namespace=()
    step "cannot make a mount namespace: the trees stay visible; the checks of which files were used still hold"
  }
fi
export SOURCE=$source BUILD=$build TMP=$tmp HIDE=$hide EXE=$exe VTEST=$vtest MODELS=$models \
  PLUGINS=$plugins OPENVINO=$openvino PYTHON=$python PYDIR=$pydir
"${namespace[@]}" bash "$tmp/runs.sh"
step "ok ($(elapsed))"
