#!/usr/bin/env python3
"""Who is who in vtest.avi's frames FIRST..LAST, for the RTSP outage tests (test_rtsp.cpp): the
confirmed tracks of jointflow-track on every frame of the file, offline, as
{"frames": {"540": [[id, centre x, centre y, height], ...], ...}}.

  build/apps/jointflow-track vtest.avi --backend openvino --max-frames 701 --output-json full.jsonl
  tests/rtsp/make_vtest_reference.py full.jsonl 480 700 > tests/rtsp/vtest_reference.json

At every frame, without gaps, the tracker keeps the ids of that stretch: the crops of each id at
frames 480, 510, ..., 680 were checked by eye to show one person each. A live run, which sees a
frame in five or so and outages of seconds, is measured against it.
"""
import json
import sys

path, first, last = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
frames = {}
for line in open(path):
    record = json.loads(line)
    if not first <= record["frame"] <= last:
        continue
    frames[str(record["frame"])] = [
        [o["id"], round(o["x"] + o["w"] / 2), round(o["y"] + o["h"] / 2), round(o["h"])]
        for o in record["objects"] if not o["tentative"]]
json.dump({"source": "vtest.avi", "first": first, "last": last, "frames": frames}, sys.stdout,
          separators=(",", ":"))
sys.stdout.write("\n")
