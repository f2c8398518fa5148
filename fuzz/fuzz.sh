#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (address + undefined behaviour sanitizers) and
# runs each for a while: `fuzz/fuzz.sh [seconds per target, default 300]` (`make fuzz`).
#
# Installs clang-14 and libclang-rt-14-dev from Debian when missing (idempotent); `make test`
# does not need them. The targets are compiled from the core sources they exercise rather than
# through Meson, because only a handful of files are involved and the rest of the core (OpenCV
# dnn models) must not be rebuilt with clang for this.
#
# Output in build-fuzz/: the growing corpus (corpus/<target>/, seeded from fuzz/corpus/) and the
# inputs that crash or hang (artifacts/<target>/). Add every one of those to
# tests/hardening/fuzz_regressions/ and fix the bug.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-300}
OUT=build-fuzz

need=()
for p in clang-14 libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
fi

CXX=clang++-14
FLAGS=(-std=c++17 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined
       -fno-sanitize-recover=undefined -Icore/include -Icore/io $(pkg-config --cflags opencv4))
LIBS=($(pkg-config --libs-only-L opencv4) -lopencv_imgproc -lopencv_core)

# target name -> its sources (the fuzz entry point first).
declare -A SOURCES=(
  [posetrack]="fuzz/posetrack_fuzz.cpp core/io/json_fields.cpp core/io/posetrack_joints.cpp
               core/io/posetrack_read.cpp core/io/posetrack_write.cpp core/eval/average_precision.cpp
               core/eval/evaluation.cpp core/eval/frame_matching.cpp core/eval/linear_assignment.cpp
               core/eval/mot_accumulator.cpp core/association/matching.cpp"
)
declare -A DICTS=([posetrack]=fuzz/posetrack.dict)

mkdir -p "$OUT"
for target in "${!SOURCES[@]}"; do
  exe="$OUT/${target}_fuzz"
  # shellcheck disable=SC2086
  srcs=(${SOURCES[$target]})
  if [ ! -x "$exe" ] || [ -n "$(find "${srcs[@]}" core/include fuzz -newer "$exe" -print -quit)" ]; then
    echo "fuzz: building $exe"
    $CXX "${FLAGS[@]}" "${srcs[@]}" "${LIBS[@]}" -o "$exe"
  fi
  [ "$SECONDS_PER_TARGET" -eq 0 ] && continue
  mkdir -p "$OUT/corpus/$target" "$OUT/artifacts/$target"
  cp -n fuzz/corpus/"$target"/* "$OUT/corpus/$target/"
  # Real sequence files make good seeds where the evaluation data is at hand (not ours to ship:
  # they stay in the build folder).
  data=${JOINTFLOW_DATA:-../shared/data}
  if [ "$target" = posetrack ] && [ -d "$data" ]; then
    find "$data" -name '*.json' -size -64k -exec cp -n {} "$OUT/corpus/$target/" \;
  fi
  echo "fuzz: running $target for ${SECONDS_PER_TARGET}s"
  "$exe" "$OUT/corpus/$target" -dict="${DICTS[$target]}" -max_total_time="$SECONDS_PER_TARGET" \
    -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$OUT/artifacts/$target/" > "$OUT/$target.log" 2>&1 || {
    echo "fuzz: $target found a crash or a hang; see $OUT/$target.log and $OUT/artifacts/$target/"
    grep -m1 -A12 -e "ERROR:" -e "terminate called" "$OUT/$target.log"
    exit 1
  }
  tail -n 8 "$OUT/$target.log"
done
