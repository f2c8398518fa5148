"""Bad frames get a clear TypeError or ValueError, and the tracker goes on afterwards."""

import numpy as np
import pytest

import jointflow


@pytest.fixture(scope="module")
def tracker():
    return jointflow.Tracker()


FRAME = np.zeros((96, 128, 3), np.uint8)


@pytest.mark.parametrize("frame, error, words", [
    ([[[0, 0, 0]]], TypeError, "expected a numpy.ndarray"),
    (b"\0" * 27, TypeError, "expected a numpy.ndarray"),
    (FRAME.astype(np.float32), TypeError, "expected dtype uint8, got float32"),
    (FRAME.astype(np.uint16), TypeError, "expected dtype uint8, got uint16"),
    (FRAME.astype(np.int8), TypeError, "expected dtype uint8, got int8"),
    (FRAME[..., 0], ValueError, "expected shape (H, W, 3), got (96, 128); a grey frame"),
    (np.zeros((96, 128, 4), np.uint8), ValueError, "got (96, 128, 4); a 4-channel frame"),
    (np.zeros((2, 96, 128, 3), np.uint8), ValueError, "got (2, 96, 128, 3)"),
    (np.zeros((0, 128, 3), np.uint8), ValueError, "frame: empty, shape (0, 128, 3)"),
    (np.zeros((96, 0, 3), np.uint8), ValueError, "frame: empty"),
    (FRAME[:, ::2], ValueError, "numpy.ascontiguousarray(frame)"),
    (FRAME[..., ::-1], ValueError, "rgb=True instead of reversing the channels"),
    (FRAME[::-1], ValueError, "not contiguous"),
    (np.asfortranarray(FRAME), ValueError, "not contiguous"),
    (np.zeros((3, 96, 128), np.uint8).transpose(1, 2, 0), ValueError, "not contiguous"),
])
def test_bad_frame(tracker, frame, error, words):
    with pytest.raises(error) as e:
        tracker.process(frame)
    assert words in str(e.value)
    assert tracker.process(FRAME) == []  # nothing lost: the next frame is tracked


def test_bad_timestamps(tracker):
    with pytest.raises(TypeError, match="timestamp"):
        tracker.process(FRAME, timestamp="1.0")
    with pytest.raises(TypeError, match="timestamp"):
        tracker.predict(None)
    with pytest.raises(TypeError):
        tracker.process(FRAME, rgb="yes")


def test_read_only_and_odd_frames_work(tracker):
    frame = FRAME.copy()
    frame.flags.writeable = False
    assert tracker.process(frame) == []
    assert tracker.process(np.zeros((16, 16, 3), np.uint8)) == []
    assert tracker.process(np.zeros((16, 1000, 3), np.uint8)) == []


def test_too_small_frame_gets_the_core_message(tracker):
    with pytest.raises(ValueError, match="too small: the spatial models need at least 16x16"):
        tracker.process(np.zeros((1, 1, 3), np.uint8))
    assert tracker.process(FRAME) == []
