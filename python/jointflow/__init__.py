"""JointFlow: online multi-person 2D pose tracking (Temporal Flow Fields, BMVC 2018).

    import cv2, jointflow
    tracker = jointflow.Tracker(similarity="oks")
    for pose in tracker.process(cv2.imread("frame.png")):
        print(pose.id, pose.box, pose.keypoints[0])   # keypoints: (17, 3) x, y, score

jointflow.settings() lists the Tracker's settings; jointflow.gst reads the poses that the
GStreamer element jointflowtrack attaches to buffers (imported on first use: it needs PyGObject).
"""

import collections as _collections
import os as _os
import pathlib as _pathlib

# An installed package (pip) carries the shipped models beside it; the core finds them through
# JOINTFLOW_MODELS_DIR, which a user's own setting overrides. In a build folder there is no
# models/ here and the core uses the source tree's.
_models = _pathlib.Path(__file__).resolve().parent / "models"
if (_models / "movenet_multipose.onnx").is_file() and not _os.environ.get("JOINTFLOW_MODELS_DIR"):
    _os.environ["JOINTFLOW_MODELS_DIR"] = str(_models)

import numpy as _np  # noqa: E402

from ._jointflow import (  # noqa: E402
    KEYPOINT_NAMES,
    SKELETON,
    Pose,
    Tracker,
    __version__,
    _pybind11_version,
    _settings_schema,
)
from .draw import draw  # noqa: E402

# pybind11 before 2.12 (Debian bookworm has 2.10) reads numpy's dtype structs as numpy 1.x lays
# them out: with numpy 2 its array checks would read the wrong fields.
if int(_np.__version__.split(".")[0]) >= 2 and _pybind11_version < (2, 12):
    raise ImportError(
        f"jointflow was built with pybind11 {'.'.join(map(str, _pybind11_version))}, which "
        f"supports numpy 1.x only, but numpy {_np.__version__} is installed: "
        "pip install 'numpy<2' (or rebuild with pybind11 >= 2.12)"
    )

Setting = _collections.namedtuple("Setting", "name type default range choices doc")
Setting.__doc__ = """A keyword of jointflow.Tracker: its name, Python type, default, (min, max)
for numbers, the accepted names for a choice, and what it does."""


def settings():
    """The settings of jointflow.Tracker, in the order the GStreamer element lists them."""
    return [Setting(**row) for row in _settings_schema()]


def __getattr__(name):
    # jointflow.gst without importing gi (PyGObject) at `import jointflow`.
    if name == "gst":
        import importlib

        try:
            return importlib.import_module(".gst", __name__)
        except ImportError as e:
            raise ImportError(
                f"jointflow.gst is unavailable ({e}); it needs PyGObject and GStreamer "
                "(Debian: python3-gi python3-gst-1.0) and a jointflow built with python-gi-dev"
            ) from e
    raise AttributeError(f"module 'jointflow' has no attribute '{name}'")


__all__ = ["KEYPOINT_NAMES", "SKELETON", "Pose", "Setting", "Tracker", "draw", "settings"]
