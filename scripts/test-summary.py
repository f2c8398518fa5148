#!/usr/bin/env python3
"""Prints closing lines for `meson test` runs from their JSON logs:
'tests: N passed, N failed, N skipped', then one line per skipped or failed suite with its reason.

Meson's own summary is a table; CI reads plain lines. A suite counts as skipped when its program
exited 77 (the Catch2 suites do when any case could not run, tests/catch_main.cpp); the reason is
the first line of its output that says SKIP."""
import json
import sys

logs = sys.argv[1:] or ["build/meson-logs/testlog.json"]
counts = {"passed": 0, "failed": 0, "skipped": 0}
notes = []
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
print(f"tests: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
for n in notes:
    print(n)
sys.exit(1 if counts["failed"] else 0)
