"""The wheel: `pip wheel` of the repository (meson-python, without build isolation: Debian's
meson, ninja and pybind11), installed in a fresh venv without system site-packages, imported there
from outside the source tree, and tracking with the models it ships: the same poses as the module
of the build folder. Builds the core again (static, into the module): minutes, hence its own
target, `make test-python-wheel`."""

import json
import os
import pathlib
import shutil
import subprocess
import sys
import zipfile

import numpy as np
import pytest

from conftest import SOURCE_ROOT, read_frames

import jointflow

BUILD = pathlib.Path(os.environ.get("PYTHONPATH", "build/python").split(":")[0]).parent
NUMPY_PIN = "numpy==1.26.4"

CHECK = r"""
import json, os, pathlib, sys
import numpy as np
import jointflow
here = pathlib.Path(jointflow.__file__).parent
assert str(here).startswith(sys.prefix), here
assert os.environ["JOINTFLOW_MODELS_DIR"] == str(here / "models")
poses = jointflow.Tracker().process(np.load(sys.argv[1]))
try:
    jointflow.gst
    gst = "imported"
except ImportError as e:
    gst = str(e)
print(json.dumps({"gst": gst, "poses": [p.keypoints.tolist() for p in poses]}))
"""


def run(*command, **kwargs):
    return subprocess.run([str(c) for c in command], check=True, text=True, **kwargs)


def test_wheel_builds_installs_and_tracks(tmp_path):
    dist = BUILD / "wheel-dist"
    shutil.rmtree(dist, ignore_errors=True)
    # The build folder is kept between runs, so that a second run recompiles only what changed.
    run(sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps",
        "--disable-pip-version-check", f"--config-settings=build-dir={BUILD / 'wheel-build'}",
        "-w", dist, SOURCE_ROOT)
    wheels = list(dist.glob("jointflow-*.whl"))
    assert len(wheels) == 1, wheels
    names = zipfile.ZipFile(wheels[0]).namelist()
    for model in ("movenet_multipose.onnx", "posenet_mobilenetv1.onnx", "tff_movenet.onnx"):
        assert f"jointflow/models/{model}" in names
    assert any(n.startswith("jointflow/_jointflow.") and n.endswith(".so") for n in names)
    assert not any("libjointflow-core" in n for n in names), "the core is linked in"

    venv = tmp_path / "venv"
    run(sys.executable, "-m", "venv", venv)
    python = venv / "bin" / "python"
    try:
        run(python, "-m", "pip", "install", "-q", "--disable-pip-version-check", NUMPY_PIN)
    except subprocess.CalledProcessError:
        pytest.skip(f"{NUMPY_PIN} could not be installed into a fresh venv (no registry?)")
    run(python, "-m", "pip", "install", "-q", "--no-deps", "--disable-pip-version-check", wheels[0])

    frame = read_frames([200])[200]
    np.save(tmp_path / "frame.npy", frame)
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "JOINTFLOW_MODELS_DIR", "VIRTUAL_ENV")}
    out = run(python, "-c", CHECK, tmp_path / "frame.npy", cwd=tmp_path, env=env,
              capture_output=True).stdout
    result = json.loads(out)
    assert "jointflow.gst is unavailable" in result["gst"]  # no PyGObject in a bare venv

    expected = sorted(p.keypoints.tolist() for p in jointflow.Tracker().process(frame))
    got = sorted(result["poses"])
    assert len(got) == len(expected) >= 3
    np.testing.assert_allclose(np.array(got), np.array(expected), rtol=0, atol=1e-4)
