#!/usr/bin/env python3
"""Re-tracks jointflow-track's poses with another tracker, for bench/peer_trackers.py: reads the
JSON Lines of `jointflow-track --output-json` (the product's own poses, default settings) and
writes a MOTChallenge file with the peer's ids. Runs inside the peer's own venv
(bench/peer_venv.sh): ByteTrack needs numpy 2, Norfair numpy 1.
   peer_track.py bytetrack POSES.jsonl OUT.txt [--threshold 0.3]
   peer_track.py norfair POSES.jsonl OUT.txt [--reach 40]

ByteTrack (roboflow `trackers`): boxes and person scores; both of its score thresholds (a new
track, the first pass) at --threshold, since MoveNet's person scores on vtest.avi lie at
0.15-0.6, under the 0.7 and 0.6 it assumes; its frame rate from the frames' timestamps (its
lost-track buffer is counted in frames of 30 frames/s and scaled by it).
Norfair: the 17 keypoints, matched by its keypoint vote with the values of its OpenPose demo
(a keypoint counts from score 0.2; a track matches below distance 0.3); a keypoint matches
within 1/--reach of the frame's height."""
import argparse
import json

import numpy as np

KEYPOINTS = ["nose", "left_eye", "right_eye", "left_ear", "right_ear", "left_shoulder",
             "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist",
             "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle"]


def read_frames(path):
    with open(path) as lines:
        return [json.loads(line) for line in lines if line.strip()]


def frame_rate(frames):
    """Frames per second from the records' timestamps (ns), 30 without them."""
    stamps = [r["timestamp"] for r in frames if r.get("timestamp") is not None]
    steps = np.diff(stamps)
    return 1e9 / float(np.median(steps)) if len(steps) else 30.0


def bytetrack(frames, threshold):
    import supervision as sv
    from trackers import ByteTrackTracker
    tracker = ByteTrackTracker(track_activation_threshold=threshold,
                               high_conf_det_threshold=threshold, frame_rate=frame_rate(frames))
    for record in frames:
        objects = record["objects"]
        boxes = np.array([[o["x"], o["y"], o["x"] + o["w"], o["y"] + o["h"]] for o in objects],
                         dtype=np.float32).reshape(-1, 4)
        scores = np.array([o["confidence"] for o in objects], dtype=np.float32)
        stamp = record.get("timestamp")
        out = tracker.update(sv.Detections(xyxy=boxes, confidence=scores),
                             timestamp=None if stamp is None else stamp / 1e9)
        yield record["frame"], [(int(i), b, c) for b, c, i in
                                zip(out.xyxy, out.confidence, out.tracker_id) if i >= 0]


def norfair(frames, reach):
    import logging
    # Norfair warns on the root logger that a scalar distance (its own keypoint vote) is slow.
    logging.getLogger().setLevel(logging.ERROR)
    from norfair import Detection, Tracker
    from norfair.distances import create_keypoints_voting_distance
    detection_threshold, distance_threshold = 0.2, 0.3
    height = frames[0]["resolution"]["height"] if frames else 1
    tracker = Tracker(
        distance_function=create_keypoints_voting_distance(height / reach, detection_threshold),
        distance_threshold=distance_threshold, detection_threshold=detection_threshold)
    for record in frames:
        detections = []
        for o in record["objects"]:
            k = o["keypoints"]
            points = np.array([[k[n]["x"], k[n]["y"]] for n in KEYPOINTS], dtype=np.float64)
            scores = np.array([k[n]["score"] for n in KEYPOINTS], dtype=np.float64)
            box = np.array([o["x"], o["y"], o["x"] + o["w"], o["y"] + o["h"]])
            detections.append(Detection(points, scores=scores, data=(box, o["confidence"])))
        rows = []
        matched = {id(d) for d in detections}
        for t in tracker.update(detections=detections):
            # Only the objects matched on this frame, with the box of the pose they took, as the
            # other trackers' rows (Norfair also returns objects it coasts on their estimate).
            if t.last_detection is not None and id(t.last_detection) in matched:
                box, score = t.last_detection.data
                rows.append((t.id, box, score))
        yield record["frame"], rows


def main():
    a = argparse.ArgumentParser()
    a.add_argument("tracker", choices=["bytetrack", "norfair"])
    a.add_argument("poses")
    a.add_argument("out")
    a.add_argument("--threshold", type=float, default=0.3, help="ByteTrack's score thresholds")
    a.add_argument("--reach", type=float, default=40.0,
                   help="Norfair: a keypoint matches within the frame's height / this")
    args = a.parse_args()
    frames = read_frames(args.poses)
    rows = (bytetrack(frames, args.threshold) if args.tracker == "bytetrack"
            else norfair(frames, args.reach))
    with open(args.out, "w") as out:
        for frame, tracked in rows:
            for track_id, (x0, y0, x1, y1), score in tracked:
                out.write(f"{frame + 1},{track_id},{x0:.2f},{y0:.2f},{x1 - x0:.2f},{y1 - y0:.2f},"
                          f"{score:.4f},-1,-1,-1\n")


if __name__ == "__main__":
    main()
