#!/usr/bin/env python3
"""Prints closing lines for `meson test` runs from their JSON logs:
'tests: N passed, N failed, N skipped', then one line per skipped or failed suite with its reason.

Meson's own summary is a table; CI reads plain lines. A suite counts as skipped when its program
exited 77 (the Catch2 suites do when any case could not run, tests/catch_main.cpp); the reason is
the first line of its output that says SKIP. A failed suite's line is followed by what it said
about the failure (Catch2's FAILED blocks, or its last lines): CI shows only the end of its log,
and a failure that does not come back when run again must be readable from that alone."""
import json
import sys

logs = sys.argv[1:] or ["build/meson-logs/testlog.json"]
counts = {"passed": 0, "failed": 0, "skipped": 0}
notes = []


def failure_excerpt(output, most=40):
    """The lines around each of the first failures Catch2 reports, or the output's last lines."""
    lines = [l.rstrip() for l in output.splitlines() if l.strip()]
    marks = [i for i, l in enumerate(lines) if "FAILED" in l or "due to unexpected exception" in l]
    if not marks:
        return lines[-15:]
    out = []
    for i in marks[:3]:
        out += ["..."] + lines[max(0, i - 4):i + 8]
    return out[:most]

for log in logs:
    try:
        f = open(log, encoding="utf-8")
    except FileNotFoundError:
        continue
    with f:
        for line in f:
            if not line.strip():
                continue
            entry = json.loads(line)
            result = entry.get("result", "")
            name = entry.get("name", "?")
            if result in ("OK", "EXPECTEDFAIL"):
                counts["passed"] += 1
                continue
            output = (entry.get("stdout") or "") + (entry.get("stderr") or "")
            if result == "SKIP":
                counts["skipped"] += 1
                lines = [l.strip() for l in output.splitlines()]
                reason = next((l[5:].strip() for l in lines if l.startswith("SKIP:  ")),
                              next((l for l in lines if "SKIP" in l), ""))
                notes.append(f"  skipped {name}: {reason or 'exit status 77'}")
            else:
                counts["failed"] += 1
                notes.append(f"  failed  {name}: {result}")
                notes += ["    " + l for l in failure_excerpt(output)]
print(f"tests: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
for n in notes:
    print(n)
sys.exit(1 if counts["failed"] else 0)
