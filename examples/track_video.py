#!/usr/bin/env python3
"""Pose tracking of a video with the jointflow Python module: OpenCV reads the frames, the tracker
follows every person, and the poses are printed and drawn.

    python3 examples/track_video.py VIDEO [--output out.mp4 | --show] [--max-frames N]
                                    [--setting NAME=VALUE ...]

prints one line per person per frame: "frame N id I score S box x,y,w,h nose x,y". With
--output the frames are written with the skeletons drawn; with --show they are shown in a window
(q quits). Needs cv2 (Debian: python3-opencv, or pip install opencv-python).
"""

import argparse
import ast
import sys

import cv2

import jointflow


def setting(text):
    name, _, value = text.partition("=")
    try:
        value = ast.literal_eval(value)  # numbers and True/False typed; anything else is text
    except (ValueError, SyntaxError):
        pass
    return name, value


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("video", help="video file or camera index (0)")
    parser.add_argument("--output", help="video file to write the drawn frames to (.mp4, .avi)")
    parser.add_argument("--show", action="store_true", help="show the drawn frames in a window")
    parser.add_argument("--max-frames", type=int, default=0, help="stop after N frames (0: all)")
    parser.add_argument("--setting", action="append", type=setting, default=[],
                        metavar="NAME=VALUE", help="a Tracker setting, e.g. similarity=tff")
    args = parser.parse_args()

    source = int(args.video) if args.video.isdigit() else args.video
    capture = cv2.VideoCapture(source)
    if not capture.isOpened():
        sys.exit(f"track_video.py: cannot open {args.video}")
    fps = capture.get(cv2.CAP_PROP_FPS) or 30.0
    try:
        tracker = jointflow.Tracker(**dict(args.setting))
    except (TypeError, ValueError) as e:
        sys.exit(f"track_video.py: {e}")
    writer = None
    frame_index = 0
    while args.max_frames <= 0 or frame_index < args.max_frames:
        ok, frame = capture.read()
        if not ok:
            break
        # Stream time of the frame (the container's, else the frame rate's): tracks are kept
        # for lost_time seconds whatever the frame rate.
        msec = capture.get(cv2.CAP_PROP_POS_MSEC)
        timestamp = msec / 1000.0 if msec > 0 or frame_index == 0 else frame_index / fps
        poses = tracker.process(frame, timestamp=timestamp)
        for p in poses:
            x, y, w, h = p.box
            nose = p.keypoints[0]
            print(f"frame {frame_index} id {p.id}{'?' if p.tentative else ''} score {p.score:.2f} "
                  f"box {x:.0f},{y:.0f},{w:.0f},{h:.0f} nose {nose[0]:.1f},{nose[1]:.1f}")
        if args.output or args.show:
            jointflow.draw(frame, poses)
        if args.output:
            if writer is None:
                fourcc = cv2.VideoWriter_fourcc(*("mp4v" if args.output.endswith(".mp4") else "MJPG"))
                writer = cv2.VideoWriter(args.output, fourcc, fps, (frame.shape[1], frame.shape[0]))
                if not writer.isOpened():
                    sys.exit(f"track_video.py: cannot write {args.output}")
            writer.write(frame)
        if args.show:
            cv2.imshow("jointflow", frame)
            if cv2.waitKey(1) & 0xFF == ord("q"):
                break
        frame_index += 1
    if writer is not None:
        writer.release()
    print(f"{frame_index} frames", file=sys.stderr)


if __name__ == "__main__":
    main()
