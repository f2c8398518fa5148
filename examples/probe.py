#!/usr/bin/env python3
"""The poses of a GStreamer pipeline, read in a pad probe: jointflowtrack attaches them to every
buffer (GstJointFlowMeta) and jointflow.gst.poses() reads them.

    python3 examples/probe.py VIDEO [--max-frames N] [--property NAME=VALUE ...]

prints one line per frame: "frame N pts SECONDS ids: 1 2 3" (ids of tentative tracks with a '?').
The plugin must be on GST_PLUGIN_PATH (build/gst-plugin in a build folder) and jointflow on
PYTHONPATH (build/python) or installed with pip.
"""

import argparse
import sys

import gi

gi.require_version("Gst", "1.0")
from gi.repository import Gst  # noqa: E402

import jointflow  # noqa: E402
import jointflow.gst  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("video", help="a video file GStreamer can decode")
    parser.add_argument("--max-frames", type=int, default=0, help="stop after N frames (0: all)")
    parser.add_argument("--property", action="append", default=[], metavar="NAME=VALUE",
                        help="a jointflowtrack property, e.g. similarity=tff (repeatable)")
    args = parser.parse_args()

    Gst.init(None)
    if Gst.ElementFactory.find("jointflowtrack") is None:
        sys.exit("probe.py: no jointflowtrack element: set GST_PLUGIN_PATH to build/gst-plugin")
    properties = " ".join(args.property)
    # A file, not a camera: every frame as fast as it decodes. A sink on the clock (sync=true)
    # would send QoS upstream and videoconvert would drop the frames that came late.
    pipeline = Gst.parse_launch(
        "filesrc name=source ! decodebin ! videoconvert ! "
        f"jointflowtrack name=track {properties} ! fakesink sync=false")
    pipeline.get_by_name("source").set_property("location", args.video)  # any file name

    frames = 0

    def on_buffer(pad, info):
        nonlocal frames
        if 0 < args.max_frames <= frames:
            # Enough: the main thread stops the pipeline; buffers still under way are dropped.
            # (identity eos-after is no help: after a decoder it may let a later frame through.)
            if frames == args.max_frames:
                pipeline.post_message(Gst.Message.new_application(
                    pipeline, Gst.Structure.new_empty("probe-done")))
                frames += 1
            return Gst.PadProbeReturn.DROP
        buffer = info.get_buffer()
        poses = jointflow.gst.poses(buffer)
        ids = " ".join(f"{p.id}{'?' if p.tentative else ''}" for p in poses)
        pts = buffer.pts / Gst.SECOND if buffer.pts != Gst.CLOCK_TIME_NONE else float("nan")
        print(f"frame {frames} pts {pts:.3f} ids: {ids}", flush=True)
        frames += 1
        return Gst.PadProbeReturn.OK

    pipeline.get_by_name("track").get_static_pad("src").add_probe(Gst.PadProbeType.BUFFER, on_buffer)

    pipeline.set_state(Gst.State.PLAYING)
    bus = pipeline.get_bus()
    message = bus.timed_pop_filtered(
        Gst.CLOCK_TIME_NONE,
        Gst.MessageType.EOS | Gst.MessageType.ERROR | Gst.MessageType.APPLICATION)
    pipeline.set_state(Gst.State.NULL)
    if message.type == Gst.MessageType.ERROR:
        error, debug = message.parse_error()
        sys.exit(f"probe.py: {error.message} ({debug})")
    print(f"{min(frames, args.max_frames) if args.max_frames > 0 else frames} frames", file=sys.stderr)


if __name__ == "__main__":
    main()
