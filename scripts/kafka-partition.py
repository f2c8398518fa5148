#!/usr/bin/env python3
"""Prints the Kafka partition each camera's records land in (docs/deploy.md).

jointflowmetapublish keys every message with the camera's source id and uses librdkafka's
partitioner murmur2_random: for a keyed message Java's murmur2 hash of the key, made positive,
modulo the topic's partition count. The partition is asked of librdkafka itself
(rd_kafka_msg_partitioner_murmur2, through ctypes), so the answer is the producer's; without
librdkafka the same hash is computed here. Partitions that no camera lands in leave as many
consumers of a group idle.

    scripts/kafka-partition.py --partitions 2 camera1 camera2
    scripts/kafka-partition.py --self-test    # librdkafka and this murmur2 agree, and so does
                                              # the table of docs/deploy.md
"""
import argparse
import ctypes
import ctypes.util
import random
import sys


def murmur2(data: bytes) -> int:
    """Kafka's murmur2 (org.apache.kafka.common.utils.Utils.murmur2), as an unsigned 32-bit int."""
    m, seed = 0x5BD1E995, 0x9747B28C
    h = (seed ^ len(data)) & 0xFFFFFFFF
    whole = len(data) - len(data) % 4
    for i in range(0, whole, 4):
        k = int.from_bytes(data[i:i + 4], "little")
        k = (k * m) & 0xFFFFFFFF
        k ^= k >> 24
        k = (k * m) & 0xFFFFFFFF
        h = ((h * m) & 0xFFFFFFFF) ^ k
    rest = data[whole:]
    if len(rest) == 3:
        h ^= rest[2] << 16
    if len(rest) >= 2:
        h ^= rest[1] << 8
    if rest:
        h ^= rest[0]
        h = (h * m) & 0xFFFFFFFF
    h ^= h >> 13
    h = (h * m) & 0xFFFFFFFF
    return h ^ (h >> 15)


def python_partition(key: bytes, partitions: int) -> int:
    return (murmur2(key) & 0x7FFFFFFF) % partitions


def librdkafka_partitioner():
    """librdkafka's murmur2 partitioner, or None where librdkafka cannot be loaded."""
    name = ctypes.util.find_library("rdkafka") or "librdkafka.so.1"
    try:
        fn = ctypes.CDLL(name).rd_kafka_msg_partitioner_murmur2
    except (OSError, AttributeError):
        return None
    fn.restype = ctypes.c_int32
    fn.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t, ctypes.c_int32,
                   ctypes.c_void_p, ctypes.c_void_p]
    # It reads neither the topic nor the opaque pointers: only the key and the partition count.
    return lambda key, partitions: fn(None, key, len(key), partitions, None, None)


def self_test(rdkafka):
    if rdkafka is None:
        sys.exit("kafka-partition: librdkafka cannot be loaded")
    rng = random.Random(7)
    keys = [b"camera1", b"camera2", b"", b"a", b"ab", b"abc"]
    keys += [bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40))) for _ in range(2000)]
    for key in keys:
        for partitions in (1, 2, 3, 4, 6, 12, 100):
            want, got = rdkafka(key, partitions), python_partition(key, partitions)
            if want != got:
                sys.exit(f"kafka-partition: {key!r} of {partitions}: librdkafka {want}, here {got}")
    # What docs/deploy.md says: its table of camera1-camera8, and the names that hash apart.
    table = {2: [1, 1, 0, 0, 0, 0, 1, 0], 3: [2, 1, 2, 1, 2, 1, 2, 2], 4: [3, 1, 0, 0, 0, 2, 1, 2],
             6: [5, 1, 2, 4, 2, 4, 5, 2], 12: [11, 1, 8, 4, 8, 10, 5, 2]}
    for partitions, row in table.items():
        got = [rdkafka(f"camera{i}".encode(), partitions) for i in range(1, 9)]
        assert got == row, f"{partitions} partitions: {got}, docs/deploy.md says {row}"
    assert [rdkafka(k, 2) for k in (b"cam-01", b"cam-02")] == [1, 0]
    print(f"kafka-partition: librdkafka and murmur2 here agree on {len(keys)} keys")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cameras", nargs="*", help="source ids (the Kafka message keys)")
    parser.add_argument("--partitions", type=int, default=2, help="the topic's partition count")
    parser.add_argument("--self-test", action="store_true",
                        help="check this file's murmur2 against librdkafka's partitioner")
    args = parser.parse_args()
    rdkafka = librdkafka_partitioner()
    if args.self_test:
        self_test(rdkafka)
        return
    if not args.cameras or args.partitions < 1:
        parser.error("name at least one camera and a partition count of 1 or more")
    partition = rdkafka or python_partition
    used = {}
    for camera in args.cameras:
        p = partition(camera.encode(), args.partitions)
        used.setdefault(p, []).append(camera)
        print(f"{camera}\tpartition {p} of {args.partitions}")
    idle = [p for p in range(args.partitions) if p not in used]
    if idle:
        print(f"no camera in partition{'s' if len(idle) > 1 else ''} "
              f"{', '.join(map(str, idle))}: a consumer group of {args.partitions} leaves "
              f"{len(idle)} idle")
    if rdkafka is None:
        print("(librdkafka not found: computed with this file's murmur2)", file=sys.stderr)


if __name__ == "__main__":
    main()
