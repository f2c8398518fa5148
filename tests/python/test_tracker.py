"""jointflow.Tracker on real frames: the poses of the C++ core, ids that hold, stream time, no
copy of the frame, the GIL released while the networks run."""

import json
import os
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import jointflow

INPUT_SIZE = "max:640"


def match(a, b):
    """Pairs each pose of `a` with the pose of `b` whose keypoints are nearest."""
    pairs = []
    left = list(b)
    for p in a:
        best = min(left, key=lambda q: float(np.abs(q["keypoints"][:, :2] - p["keypoints"][:, :2]).max()))
        left.remove(best)
        pairs.append((p, best))
    return pairs


def as_dicts(poses):
    return [{"score": p.score, "box": np.array(p.box), "keypoints": p.keypoints} for p in poses]


def test_frame_200_equals_estimate_image(vtest_frames, tmp_path):
    cv2 = pytest.importorskip("cv2")
    exe = os.environ.get("JOINTFLOW_ESTIMATE_IMAGE")
    if not exe or not pathlib.Path(exe).is_file():
        pytest.skip("estimate_image was not built (it needs CLI11)")
    frame = vtest_frames[200]
    png = tmp_path / "vtest-200.png"
    assert cv2.imwrite(str(png), frame)
    out = subprocess.run([exe, str(png), "--model", "movenet", "--input-size", INPUT_SIZE],
                         check=True, capture_output=True, text=True).stdout
    reference = [{"score": p["score"], "box": np.array(p["box"], dtype=np.float32),
                  "keypoints": np.array(p["keypoints"], dtype=np.float32)}
                 for p in json.loads(out)["poses"]]
    assert len(reference) >= 3, "vtest frame 200 shows several people"

    tracker = jointflow.Tracker(model_type="movenet", input_size=INPUT_SIZE)
    poses = tracker.process(cv2.imread(str(png)))
    assert len(poses) == len(reference)
    for ours, theirs in match(as_dicts(poses), reference):
        assert ours["keypoints"].shape == (17, 3) and ours["keypoints"].dtype == np.float32
        np.testing.assert_allclose(ours["keypoints"], theirs["keypoints"], rtol=0, atol=1e-4)
        np.testing.assert_allclose(ours["box"], theirs["box"], rtol=0, atol=1e-4)
        assert abs(ours["score"] - theirs["score"]) <= 1e-4
    # The first frame starts a track per person.
    assert sorted(p.id for p in poses) == list(range(1, len(poses) + 1))
    assert all(p.tentative and p.age == 0 for p in poses)


def test_rgb_flag_gives_the_same_poses(vtest_frames):
    frame = vtest_frames[200]
    bgr = jointflow.Tracker().process(frame)
    rgb = jointflow.Tracker().process(np.ascontiguousarray(frame[..., ::-1]), rgb=True)
    assert len(bgr) == len(rgb) > 0
    for a, b in match(as_dicts(bgr), as_dicts(rgb)):
        np.testing.assert_allclose(a["keypoints"], b["keypoints"], rtol=0, atol=1e-3)


def test_ids_hold_over_frames(vtest_frames):
    tracker = jointflow.Tracker()
    seen = []
    for i in range(30):
        poses = tracker.process(vtest_frames[i], timestamp=i / 10.0)
        seen.append({p.id for p in poses})
        # Nobody left and came back in these 3 s, so no id changed (previous_id is set only for
        # a person recognised late by re-entry).
        assert all(p.previous_id == 0 for p in poses), [p.previous_id for p in poses]
    # People walk through the scene: most ids of a frame were there on the frame before.
    kept = [len(a & b) / max(len(b), 1) for a, b in zip(seen, seen[1:])]
    assert np.mean(kept) > 0.8, kept
    last = tracker.process(vtest_frames[29], timestamp=3.0)  # same frame again, 0.1 s later
    long_lived = [p for p in last if p.age >= 20]
    assert long_lived, "someone is tracked over the 30 frames"
    for p in long_lived:
        assert not p.tentative
        # Frames came 0.1 s apart: the age in seconds is the age in frames over 10.
        assert p.age_seconds == pytest.approx(p.age / 10.0, abs=1e-6)


def test_predict_and_reset(vtest_frames):
    tracker = jointflow.Tracker()
    for i in range(3):
        poses = tracker.process(vtest_frames[i], timestamp=i / 25.0)
    predicted = tracker.predict(3 / 25.0)
    assert {p.id for p in predicted} == {p.id for p in poses}
    again = tracker.predict(3 / 25.0)  # the tracker is not changed by predict
    assert [p.keypoints.tolist() for p in predicted] == [p.keypoints.tolist() for p in again]
    tracker.reset()
    assert tracker.predict(4 / 25.0) == []
    after = tracker.process(vtest_frames[3], timestamp=4 / 25.0)
    assert after and min(p.id for p in after) > max(p.id for p in poses), "ids keep counting up"


def test_no_copy_of_contiguous_frames(vtest_frames):
    frame = vtest_frames[0]
    assert frame.flags.c_contiguous
    tracker = jointflow.Tracker()
    tracker.process(frame)
    assert tracker._frame_address == frame.ctypes.data
    rgb = np.ascontiguousarray(frame[..., ::-1])
    tracker.process(rgb, rgb=True)
    assert tracker._frame_address == rgb.ctypes.data
    # A crop keeps packed pixels with a longer row step: wrapped in place too.
    crop = frame[100:400, 50:700]
    tracker.process(crop)
    assert tracker._frame_address == crop.ctypes.data


def test_gil_is_released_while_tracking(vtest_frames):
    tracker = jointflow.Tracker(input_size="256x256")
    small = np.ascontiguousarray(vtest_frames[0][::2, ::2])
    tracker.process(small)  # models warm
    ticks = 0
    running = threading.Event()
    done = threading.Event()

    def count():
        nonlocal ticks
        running.set()
        while not done.is_set():
            ticks += 1
            time.sleep(0)  # lets the GIL go at once: this thread never holds it for long

    # With a long switch interval the counting thread gets the GIL only when this one lets it
    # go: were the GIL held through process(), not one tick would fall inside the call (checked
    # with a builtin that holds it: 0 ticks, where a 0.3 s sleep gives thousands).
    interval = sys.getswitchinterval()
    sys.setswitchinterval(30.0)
    try:
        thread = threading.Thread(target=count)
        thread.start()
        running.wait()
        before = ticks
        tracker.process(small)
        during = ticks - before
        done.set()
        thread.join()
    finally:
        sys.setswitchinterval(interval)
    assert during > 10


def test_one_tracker_from_two_threads(vtest_frames):
    tracker = jointflow.Tracker()
    errors = []

    def run(start):
        try:
            for i in range(start, start + 4):
                tracker.process(vtest_frames[i])
        except Exception as e:  # noqa: BLE001 -- reported below
            errors.append(e)

    threads = [threading.Thread(target=run, args=(s,)) for s in (0, 10)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []


def test_module_constants():
    assert len(jointflow.KEYPOINT_NAMES) == 17
    assert jointflow.KEYPOINT_NAMES[0] == "nose" and jointflow.KEYPOINT_NAMES[16] == "right_ankle"
    assert len(jointflow.SKELETON) == 19
    assert all(0 <= a < 17 and 0 <= b < 17 for a, b in jointflow.SKELETON)
    assert jointflow.__version__


def test_draw(vtest_frames):
    pytest.importorskip("cv2")
    frame = vtest_frames[200].copy()
    poses = jointflow.Tracker().process(frame)
    out = jointflow.draw(frame, poses)
    assert out is frame
    assert np.any(frame != vtest_frames[200])
