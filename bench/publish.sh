#!/usr/bin/env bash
# jointflowmetapublish against local brokers (make bench-publish): runs BUILD/bench/publish-bench
# (the tracker's rate, then MQTT and Kafka, each in a process of its own) and writes
# docs/publish-bench.md. Takes about 4 minutes (two 60 s outages, Kafka's start).
#   bench/publish.sh BUILD [publish-bench options: --outage-seconds N --messages N ...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "$1" && pwd)"
shift
export GST_PLUGIN_PATH="$build/gst-plugin"
export GST_REGISTRY="$build/bench/gst-registry.bin"
bench="$build/bench/publish-bench"
out="$root/docs/publish-bench.md"
fps=$("$bench" --part tracker)
{
  echo "# jointflowmetapublish against local brokers"
  echo
  echo "\`make bench-publish\` (bench/publish.sh, bench/publish_bench.cpp): mosquitto and a Kafka"
  echo "broker on loopback, started by the bench; synthetic frames of two people (messages of about"
  echo "2 kB). Each method in a process of its own: first the outage (broker killed, 30 frames/s"
  echo "pushed for the whole outage, resident memory sampled every 5 s; then the broker restarted and"
  echo "what the queue held delivered), then the throughput (frames pushed as fast as the element"
  echo "takes them, timed until EOS has had every message acknowledged), then the latency (one"
  echo "frame every 2 ms; push + pull through the element against the same through \`identity\`)."
  echo
  echo "Tracker on vtest.avi in the same run, default settings: **$fps frames/s** (10 times that is"
  echo "the target). docs/benchmarks.md has the tracker's rate on an idle machine: up to 40"
  echo "frames/s at 256x256, i.e. a target of 400 messages/s."
  "$bench" --part mqtt --tracker-fps "$fps" "$@"
  "$bench" --part kafka --tracker-fps "$fps" --kafka-jars "$build/kafka-jars" \
    --log4j "$root/tests/publish/kafka-log4j2.properties" "$@"
  echo
  echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores ($(uptime | sed 's/.*load average/load average/'))."
} > "$out.tmp"
mv "$out.tmp" "$out"
cat "$out"
