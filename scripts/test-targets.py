"""The ninja targets that the named meson tests need: each test's program where the build makes
it, and the targets it depends on (meson introspect). `make test-asan` builds only these in the
sanitizer build, so that code no sanitizer suite runs (benchmarks, apps, examples) is not compiled
a second time with the sanitizers (5x the compile time of a release object).

usage: test-targets.py BUILD_DIR TEST_NAME...
"""
import json
import os
import subprocess
import sys


def introspect(build, what):
    out = subprocess.run(["meson", "introspect", build, what], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)


def main(build, names):
    build = os.path.abspath(build)
    tests = {t["name"]: t for t in introspect(build, "--tests")}
    targets = introspect(build, "--targets")
    files_of = {t["id"]: t["filename"] for t in targets}
    built = {f for files in files_of.values() for f in files}
    missing = [n for n in names if n not in tests]
    if missing:
        sys.exit(f"test-targets: no such test in {build}: {' '.join(missing)}")
    wanted = set()
    for name in names:
        test = tests[name]
        if test["cmd"] and test["cmd"][0] in built:
            wanted.add(test["cmd"][0])
        for dep in test["depends"]:
            wanted.update(files_of.get(dep, []))
    print(" ".join(sorted(os.path.relpath(f, build) for f in wanted)))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
