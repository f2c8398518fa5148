#!/usr/bin/env python3
"""Reads the poses that jointflowmetapublish (or `jointflow-track --publish`) sends, from Kafka
or MQTT, and prints per camera the people present and the tracks that ended.

Each message is one frame's record (docs/gstreamer.md, jointflowjsonwriter): `source_id` names
the camera, `objects` holds the people with their track `id`. A track has ended when its id has
not been seen for --end-after frames of its camera.

Kafka: run as many copies as the topic has partitions with the same --group; Kafka spreads the
partitions over them, and since the camera (source_id) is the message key, each camera's frames
go to one consumer, in order (docs/deploy.md).

    pip install confluent-kafka==2.16.1 paho-mqtt==2.2.0
    python3 examples/consumer.py kafka://kafka:9092/poses --group pose-readers
    python3 examples/consumer.py mqtt://broker:1883/poses/#
"""
import argparse
import json
import signal
import sys
import time
from urllib.parse import unquote, urlparse


class Camera:
    """What one camera shows: the tracks present now and when each was last seen."""

    def __init__(self, name, end_after):
        self.name = name
        self.end_after = end_after
        self.last_seen = {}  # track id -> frame
        self.first_seen = {}
        self.present = []
        self.frame = -1

    def update(self, record):
        """Takes one frame's record; returns the lines to print."""
        self.frame = record["frame"]
        lines = []
        ids = sorted(o["id"] for o in record["objects"] if not o.get("tentative", False))
        for i in ids:
            self.first_seen.setdefault(i, self.frame)
            self.last_seen[i] = self.frame
        ended = sorted(i for i, f in self.last_seen.items() if self.frame - f > self.end_after)
        for i in ended:
            lines.append(f"{self.name} frame {self.frame}: track {i} ended "
                         f"(frames {self.first_seen[i]}-{self.last_seen[i]})")
            del self.last_seen[i]
            del self.first_seen[i]
        if ids != self.present:
            self.present = ids
            lines.append(f"{self.name} frame {self.frame}: {len(ids)} present "
                         f"{ids if ids else '[]'}")
        return lines

    def finish(self):
        """At the end of the input every track still open ends."""
        return [f"{self.name} end: track {i} ended (frames {self.first_seen[i]}-{f})"
                for i, f in sorted(self.last_seen.items())]


class Tracker:
    def __init__(self, end_after):
        self.end_after = end_after
        self.cameras = {}

    def message(self, payload):
        try:
            record = json.loads(payload)
            name = record.get("source_id", "(no source_id)")
            record["frame"], record["objects"]  # the fields this program needs
        except (ValueError, KeyError, TypeError) as e:
            print(f"skipped a message that is not a JointFlow record: {e}", file=sys.stderr)
            return
        camera = self.cameras.setdefault(name, Camera(name, self.end_after))
        for line in camera.update(record):
            print(line, flush=True)

    def finish(self):
        for name in sorted(self.cameras):
            for line in self.cameras[name].finish():
                print(line, flush=True)


def consume_kafka(url, args, tracker, stop):
    from confluent_kafka import Consumer, KafkaException

    consumer = Consumer({
        "bootstrap.servers": f"{url.hostname}:{url.port or 9092}",
        "group.id": args.group,
        "auto.offset.reset": "earliest" if args.from_beginning else "latest",
        "enable.auto.commit": True,
    })
    consumer.subscribe([args.topic])
    count, idle_since = 0, time.monotonic()
    try:
        while not stop() and (args.max_messages == 0 or count < args.max_messages):
            msg = consumer.poll(0.2)
            if msg is None:
                if args.idle_timeout and time.monotonic() - idle_since > args.idle_timeout:
                    break
                continue
            if msg.error():
                raise KafkaException(msg.error())
            idle_since = time.monotonic()
            tracker.message(msg.value())
            count += 1
    finally:
        consumer.close()


def consume_mqtt(url, args, tracker, stop):
    import paho.mqtt.client as mqtt

    received = []
    client = mqtt.Client(mqtt.CallbackAPIVersion.VERSION2, client_id=args.group,
                         clean_session=False)
    client.on_connect = lambda c, userdata, flags, rc, props: c.subscribe(args.topic, qos=1)
    client.on_message = lambda c, userdata, msg: received.append(msg.payload)
    client.connect(url.hostname, url.port or 1883)
    client.loop_start()
    count, idle_since = 0, time.monotonic()
    try:
        while not stop() and (args.max_messages == 0 or count < args.max_messages):
            if not received:
                if args.idle_timeout and time.monotonic() - idle_since > args.idle_timeout:
                    break
                time.sleep(0.05)
                continue
            idle_since = time.monotonic()
            tracker.message(received.pop(0))
            count += 1
    finally:
        client.loop_stop()
        client.disconnect()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("url", help="kafka://host:port/topic or mqtt://host:port/topic (MQTT "
                                    "wildcards allowed: mqtt://h/poses/#)")
    parser.add_argument("--group", default="jointflow-consumer",
                        help="Kafka consumer group (MQTT: the client id)")
    parser.add_argument("--end-after", type=int, default=30,
                        help="frames without a track's id before it counts as ended")
    parser.add_argument("--from-beginning", action="store_true",
                        help="Kafka: a new group starts at the oldest message, not the newest")
    parser.add_argument("--max-messages", type=int, default=0, help="stop after N (0: never)")
    parser.add_argument("--idle-timeout", type=float, default=0,
                        help="stop after this many seconds without a message (0: never)")
    args = parser.parse_args()

    url = urlparse(args.url)
    # The topic is all that follows host:port/, as written: urlparse would take the "#" of an MQTT
    # wildcard (poses/#) for the start of a fragment and drop it.
    parts = args.url.split("/", 3)
    args.topic = unquote(parts[3]) if len(parts) == 4 else ""
    if url.scheme not in ("kafka", "mqtt") or not url.hostname or not args.topic:
        parser.error(f"{args.url}: expected kafka://host:port/topic or mqtt://host:port/topic")
    stopping = []
    signal.signal(signal.SIGTERM, lambda *_: stopping.append(True))
    signal.signal(signal.SIGINT, lambda *_: stopping.append(True))
    tracker = Tracker(args.end_after)
    (consume_kafka if url.scheme == "kafka" else consume_mqtt)(url, args, tracker,
                                                               lambda: bool(stopping))
    tracker.finish()


if __name__ == "__main__":
    main()
