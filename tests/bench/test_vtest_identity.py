#!/usr/bin/env python3
"""Identity on real frames against our own labels (tests/data/vtest-identity; issue 42):
jointflow-track with its defaults on all 795 frames of vtest.avi, scored by jointflow-eval
--mot-gt per visit (re-entry off) and per person (re-entry on), as `make bench-identity-vtest`
scores it (docs/identity-vtest.md).

OpenVINO at precision f32, not the default: OpenVINO computes in bf16 where the CPU has it (this
machine) and in f32 where not, and ids on this clip follow such small differences; f32 gives
every CPU the same figures. The floors sit a little below the f32 figures of the default with
tiles (7 December 2026, evening: 4 id switches and IDF1 90.8 per visit, IDF1 96.2 per person). The default
before it, the whole frame only (`--tiles false`), fails them: 21 switches, IDF1 88.9 and 92.3;
so did the code before the swap check after step 5 and before the late recognition of
reentry.cpp. Exit 77 (skip) without vtest.avi or OpenVINO.
   test_vtest_identity.py JOINTFLOW_TRACK JOINTFLOW_EVAL SOURCE_ROOT VTEST HAVE_OPENVINO"""
import json
import os
import subprocess
import sys
import tempfile

track, evaluator, root, video, have_openvino = sys.argv[1:6]
if not os.path.isfile(video):
    print("SKIP: no %s (Debian's opencv-doc)" % video)
    sys.exit(77)
if have_openvino != "yes":
    print("SKIP: this build has no OpenVINO; the floors were measured with it")
    sys.exit(77)
labels = os.path.join(root, "tests", "data", "vtest-identity")
FLOORS = {  # (labels, re-entry): {figure: (floor or ceiling, today)}
    ("visits", "off"): {"id_switches": ("<=", 8, 4), "idf1": (">=", 89.5, 90.8)},
    ("persons", "on"): {"idf1": (">=", 94.5, 96.2)},
}

with tempfile.TemporaryDirectory() as tmp:
    runs = {}
    for reentry in ("on", "off"):
        out = os.path.join(tmp, reentry + ".txt")
        args = [track, video, "--backend", "openvino", "--precision", "f32", "-q", "--output-mot",
                out]
        if reentry == "off":
            args += ["--reentry-time", "0"]
        runs[reentry] = (subprocess.Popen(args, stderr=subprocess.PIPE, text=True), out)
    failed = []
    for (name, reentry), checks in FLOORS.items():
        proc, out = runs[reentry]
        if proc.wait() != 0:
            print("FAIL: jointflow-track (re-entry %s): %s" % (reentry, proc.stderr.read()))
            sys.exit(1)
        score = subprocess.run([evaluator, "--mot-gt", os.path.join(labels, name), "--pred", out,
                                "--json"], check=True, capture_output=True, text=True)
        combined = json.loads(score.stdout)["combined"]
        for figure, (op, bound, today) in checks.items():
            value = combined[figure]
            ok = value <= bound if op == "<=" else value >= bound
            print("figure: %s, re-entry %s: %s %s (want %s %s; %s on 7 December, with tiles)" %
                  (name, reentry, figure, round(value, 1), op, bound, today))
            if not ok:
                failed.append("%s %s %s" % (name, figure, round(value, 1)))
if failed:
    print("FAIL: " + "; ".join(failed))
    sys.exit(1)
print("ok")
