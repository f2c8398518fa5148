"""Drawing of poses on a frame with OpenCV (cv2 is needed for this function only)."""

import colorsys

import numpy as np

from ._jointflow import SKELETON


def _colour(track_id):
    # One hue per id, spaced by the golden ratio so that neighbouring ids differ; BGR.
    r, g, b = colorsys.hsv_to_rgb((track_id * 0.618034) % 1.0, 0.9, 1.0)
    return int(b * 255), int(g * 255), int(r * 255)


def draw(frame, poses, keypoint_threshold=0.2):
    """Draws each pose's skeleton, keypoints, box and id on `frame` (BGR, in place); returns it."""
    import cv2

    for pose in poses:
        colour = _colour(pose.id)
        kp = pose.keypoints
        seen = kp[:, 2] >= keypoint_threshold
        points = np.rint(kp[:, :2]).astype(int)
        for a, b in SKELETON:
            if seen[a] and seen[b]:
                cv2.line(frame, tuple(points[a]), tuple(points[b]), colour, 2, cv2.LINE_AA)
        for j in np.flatnonzero(seen):
            cv2.circle(frame, tuple(points[j]), 3, colour, -1, cv2.LINE_AA)
        x, y, w, h = (int(round(v)) for v in pose.box)
        cv2.rectangle(frame, (x, y), (x + w, y + h), colour, 1)
        label = f"{pose.id}{'?' if pose.tentative else ''}"
        cv2.putText(frame, label, (x, max(y - 4, 10)), cv2.FONT_HERSHEY_SIMPLEX, 0.5, colour, 1,
                    cv2.LINE_AA)
    return frame
