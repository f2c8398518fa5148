#!/usr/bin/env bash
# Fetches the Kafka broker the publish tests and benchmarks run (KRaft mode) into a folder of the
# build directory: the jars tests/publish/kafka-pom.xml names and their dependencies, copied by
# Maven (`dependency:copy-dependencies`) from Maven Central; Maven's local repository (~/.m2) is
# the cache, so later runs need no network. Usage: scripts/fetch-kafka.sh [BUILD_DIR]
# Exits 0 when the jars are there, 1 (saying why) when they could not be fetched: the Kafka tests
# then report themselves skipped.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(mkdir -p "${1:-$root/build}" && cd "${1:-$root/build}" && pwd)"
out="$build/kafka-jars"
pom="$root/tests/publish/kafka-pom.xml"
stamp="$out/.pom.sha256"
want="$(sha256sum "$pom" | cut -d' ' -f1)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && ls "$out"/kafka_2.13-*.jar >/dev/null 2>&1; then
  exit 0
fi
command -v mvn >/dev/null || { echo "fetch-kafka: mvn is missing (scripts/install-deps.sh installs maven)" >&2; exit 1; }
rm -rf "$out.tmp"
mkdir -p "$out.tmp"
echo "fetch-kafka: copying the Kafka broker jars into $out"
if ! timeout 600 mvn -q -B -f "$pom" dependency:copy-dependencies -DincludeScope=runtime \
     -DoutputDirectory="$out.tmp" >"$build/fetch-kafka.log" 2>&1; then
  echo "fetch-kafka: Maven could not fetch the jars (no network and no cache?); see $build/fetch-kafka.log" >&2
  tail -5 "$build/fetch-kafka.log" >&2 || true
  rm -rf "$out.tmp"
  exit 1
fi
rm -rf "$out"
mv "$out.tmp" "$out"
echo "$want" > "$stamp"
