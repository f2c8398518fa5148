"""Person correspondences between two frames, and the loss mask M, for pseudo-labelled videos.

The association is deliberately conservative (issue 6): a pair of poses is a training
correspondence only when it is confident and unambiguous; every other person, in either frame,
goes into the ignore mask M of the paper's loss (Eq. 5) so that a wrong or missing label never
teaches the network.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np

NUM_JOINTS = 17


def pose_distance(a: np.ndarray, b: np.ndarray, joint_threshold: float, min_common: int) -> float:
    """Mean distance of the joints confident in both poses ([17, 3] arrays), divided by the
    person's size (the larger side of a's keypoint box); inf with fewer than min_common joints."""
    common = (a[:, 2] >= joint_threshold) & (b[:, 2] >= joint_threshold)
    if common.sum() < min_common:
        return np.inf
    pts = a[a[:, 2] >= joint_threshold, :2]
    size = max(float(np.ptp(pts[:, 0])), float(np.ptp(pts[:, 1])), 1.0)
    return float(np.linalg.norm(a[common, :2] - b[common, :2], axis=1).mean()) / size


def associate(kps_a: Sequence[np.ndarray], kps_b: Sequence[np.ndarray], joint_threshold: float = 0.3,
              min_common: int = 6, max_distance: float = 0.25, ambiguity_ratio: float = 0.5
              ) -> List[Tuple[int, int]]:
    """Confident, unambiguous matches (i in a, k in b): mutual nearest neighbours by
    pose_distance, closer than max_distance, and the runner-up in both the row and the column at
    least 1/ambiguity_ratio times farther."""
    if not len(kps_a) or not len(kps_b):
        return []
    d = np.array([[pose_distance(a, b, joint_threshold, min_common) for b in kps_b] for a in kps_a])
    matches = []
    for i in range(d.shape[0]):
        k = int(np.argmin(d[i]))
        if not d[i, k] < max_distance or int(np.argmin(d[:, k])) != i:
            continue
        others = np.concatenate([np.delete(d[i], k), np.delete(d[:, k], i)])
        if others.size and not d[i, k] < ambiguity_ratio * others.min():
            continue
        matches.append((i, k))
    return matches


def _zero_box(mask: np.ndarray, box, margin: float, channels=slice(None)) -> None:
    h, w = mask.shape[1:]
    x0, y0 = max(0, int(np.floor(box[0] - margin))), max(0, int(np.floor(box[1] - margin)))
    x1, y1 = min(w - 1, int(np.ceil(box[2] + margin))), min(h - 1, int(np.ceil(box[3] + margin)))
    if x1 >= x0 and y1 >= y0:
        mask[channels, y0:y1 + 1, x0:x1 + 1] = 0


def keypoint_box(kps: np.ndarray, joint_threshold: float = 0.05):
    pts = kps[kps[:, 2] >= joint_threshold, :2]
    if not len(pts):
        pts = kps[:, :2]
    return (*pts.min(0), *pts.max(0))


def motions_and_mask(kps_a: Sequence[np.ndarray], kps_b: Sequence[np.ndarray],
                     matches: Sequence[Tuple[int, int]], grid_hw: Tuple[int, int],
                     joint_threshold: float = 0.3, margin: float = 3.0, ignore_joints=()):
    """Joint motions of the matched people (paper: p_(j,k)^(t-1) -> p_(j,k)^t, grid cells) and the
    mask M [17, H, W]: 0 around every unmatched person of either frame (all joints), around a
    matched person for each joint not confident in both frames, and for `ignore_joints` (joints a
    data set does not annotate) everywhere; 1 elsewhere, where no motion means a target of 0."""
    mask = np.ones((NUM_JOINTS, *grid_hw), np.float32)
    motions = []
    matched_a = {i for i, _ in matches}
    matched_b = {k for _, k in matches}
    for i, a in enumerate(kps_a):
        if i not in matched_a:
            _zero_box(mask, keypoint_box(a), margin)
    for k, b in enumerate(kps_b):
        if k not in matched_b:
            _zero_box(mask, keypoint_box(b), margin)
    for i, k in matches:
        a, b = kps_a[i], kps_b[k]
        ba, bb = keypoint_box(a), keypoint_box(b)
        union = (min(ba[0], bb[0]), min(ba[1], bb[1]), max(ba[2], bb[2]), max(ba[3], bb[3]))
        for j in range(NUM_JOINTS):
            if j in ignore_joints:
                continue
            if a[j, 2] >= joint_threshold and b[j, 2] >= joint_threshold:
                motions.append((j, (float(a[j, 0]), float(a[j, 1])), (float(b[j, 0]), float(b[j, 1]))))
            else:
                _zero_box(mask, union, margin, channels=j)
    for j in ignore_joints:
        mask[j] = 0
    return motions, mask
