"""examples/track_video.py on a few frames of vtest.avi: poses printed and drawn to a file."""

import subprocess
import sys

import pytest

from conftest import SOURCE_ROOT, VTEST


def test_track_video_prints_and_draws(tmp_path):
    cv2 = pytest.importorskip("cv2", reason="python3-opencv is not installed")
    if not VTEST.is_file():
        pytest.skip(f"{VTEST} is missing (opencv-doc)")
    out = tmp_path / "tracked.avi"
    result = subprocess.run(
        [sys.executable, str(SOURCE_ROOT / "examples" / "track_video.py"), str(VTEST),
         "--max-frames", "8", "--output", str(out), "--setting", "min_track_length=3"],
        check=True, capture_output=True, text=True, timeout=300)
    lines = result.stdout.splitlines()
    frames = {int(line.split()[1]) for line in lines}
    assert frames == set(range(8)), "someone on every frame"
    assert any("?" not in line.split()[3] for line in lines), "tracks confirmed after 3 frames"
    capture = cv2.VideoCapture(str(out))
    count = 0
    while capture.read()[0]:
        count += 1
    assert count == 8


def test_track_video_reports_a_bad_setting():
    pytest.importorskip("cv2", reason="python3-opencv is not installed")
    if not VTEST.is_file():
        pytest.skip(f"{VTEST} is missing (opencv-doc)")
    result = subprocess.run(
        [sys.executable, str(SOURCE_ROOT / "examples" / "track_video.py"), str(VTEST),
         "--setting", "similarity=nope"], capture_output=True, text=True, timeout=120)
    assert result.returncode != 0
    assert "similarity: unknown similarity 'nope'" in result.stderr
