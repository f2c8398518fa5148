#!/usr/bin/env bash
# A Kafka broker on this machine, to try docs/deploy.md without a cluster (`make kafka-local`): one
# process in KRaft mode (broker and controller), the jars the publish tests use
# (scripts/fetch-kafka.sh, Maven Central, cached in ~/.m2), run with Debian's OpenJDK, listening
# on 127.0.0.1:$KAFKA_PORT (9092). It starts empty each time and creates the topics in
# $KAFKA_TOPICS ("poses") with $KAFKA_PARTITIONS (2) partitions each, through the Python client of
# examples/consumer.py (examples/consumer-venv.sh); other topics are not created on first use, as
# on a cluster configured that way. Runs in the foreground; Ctrl-C stops it.
#   scripts/kafka-local.sh [BUILD_DIR]
#   KAFKA_PARTITIONS=3 KAFKA_TOPICS="poses poses-archive" scripts/kafka-local.sh
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(mkdir -p "${1:-$root/build}" && cd "${1:-$root/build}" && pwd)"
port=${KAFKA_PORT:-9092}
controller_port=${KAFKA_CONTROLLER_PORT:-$((port + 1))}
partitions=${KAFKA_PARTITIONS:-2}
topics=${KAFKA_TOPICS:-poses}
command -v java >/dev/null || { echo "kafka-local: java is missing (scripts/install-deps.sh installs openjdk-17-jre-headless)" >&2; exit 1; }
bash "$root/scripts/fetch-kafka.sh" "$build"
python=$(bash "$root/examples/consumer-venv.sh" "$build")

dir="$build/kafka-local"
rm -rf "$dir"
mkdir -p "$dir"
cat >"$dir/server.properties" <<EOF
process.roles=broker,controller
node.id=1
controller.quorum.voters=1@127.0.0.1:$controller_port
listeners=PLAINTEXT://127.0.0.1:$port,CONTROLLER://127.0.0.1:$controller_port
advertised.listeners=PLAINTEXT://127.0.0.1:$port
controller.listener.names=CONTROLLER
inter.broker.listener.name=PLAINTEXT
listener.security.protocol.map=PLAINTEXT:PLAINTEXT,CONTROLLER:PLAINTEXT
log.dirs=$dir/data
num.partitions=$partitions
auto.create.topics.enable=false
offsets.topic.replication.factor=1
transaction.state.log.replication.factor=1
transaction.state.log.min.isr=1
group.initial.rebalance.delay.ms=0
EOF
java=(java -Xms64m -Xmx512m -XX:+UseSerialGC -XX:TieredStopAtLevel=1 -XX:-UsePerfData
      "-Dlog4j2.configurationFile=$root/tests/publish/kafka-log4j2.properties"
      -cp "$build/kafka-jars/*")
"${java[@]}" kafka.tools.StorageTool format -t MkU3OEVBNTcwNTJENDM2Qg \
  -c "$dir/server.properties" >"$dir/format.log" 2>&1 ||
  { cat "$dir/format.log" >&2; exit 1; }

echo "kafka-local: starting the broker on 127.0.0.1:$port (log: $dir/kafka.log)"
"${java[@]}" kafka.Kafka "$dir/server.properties" >"$dir/kafka.log" 2>&1 &
broker=$!
trap 'kill "$broker" 2>/dev/null; wait "$broker" 2>/dev/null || true; echo "kafka-local: stopped"' EXIT
trap 'exit 0' INT TERM
for _ in $(seq 240); do
  grep -q "Kafka Server started" "$dir/kafka.log" && break
  kill -0 "$broker" 2>/dev/null || { tail -20 "$dir/kafka.log" >&2; exit 1; }
  sleep 0.5
done
grep -q "Kafka Server started" "$dir/kafka.log" || { echo "kafka-local: no start within 120 s" >&2; exit 1; }

"$python" - "127.0.0.1:$port" "$partitions" $topics <<'PY'
import sys
from confluent_kafka.admin import AdminClient, NewTopic

address, partitions, topics = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
admin = AdminClient({"bootstrap.servers": address})
for topic, future in admin.create_topics(
        [NewTopic(t, num_partitions=partitions, replication_factor=1) for t in topics]).items():
    future.result(timeout=60)
    print(f"kafka-local: topic {topic}, {partitions} partitions")
PY
echo "kafka-local: ready at kafka://127.0.0.1:$port/${topics%% *} (Ctrl-C stops it)"
wait "$broker"
