#!/usr/bin/env python3
"""Prints one closing line for a `meson test` run from its JSON log: 'tests: N passed, N failed'.

Meson's own summary is a table; CI reads a single plain line. Skipped counts tests that meson
itself skipped (exit 77); Catch2 cases that skip for absent data say so in the log and pass."""
import json
import sys

log = sys.argv[1] if len(sys.argv) > 1 else "build/meson-logs/testlog.json"
counts = {"passed": 0, "failed": 0, "skipped": 0}
with open(log, encoding="utf-8") as f:
    for line in f:
        if not line.strip():
            continue
        result = json.loads(line).get("result", "")
        if result in ("OK", "EXPECTEDFAIL"):
            counts["passed"] += 1
        elif result == "SKIP":
            counts["skipped"] += 1
        else:
            counts["failed"] += 1
print(f"tests: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
sys.exit(1 if counts["failed"] else 0)
