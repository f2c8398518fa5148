// A live frame's lag: how long ago it was captured, on the pipeline clock. A live source stamps
// each frame with the clock's running time at which it captured it (v4l2src) or received it
// (rtspsrc's jitter buffer, from the packets' arrival); the clock's running time now, less that,
// is the frame's age: decoding, queues, conversion and inference count, the camera's encoder and
// the network before the receiver do not. jointflowtrack's lag histogram and jointflow-track's
// --output-lag measure it the same way, here.
//
// The capture lag counts those too, where the camera says when it took the frame: an RTSP
// camera's RTCP sender reports map its RTP timestamps to its NTP wall clock, and rtspsrc with
// add-reference-timestamp-meta (jointflow-track sets it) puts that time on each frame as a
// GstReferenceTimestampMeta "timestamp/x-ntp", which decoders and converters carry on. This
// host's wall clock now, less it, is the frame's age since the camera stamped it: its encoder,
// the network, the jitter buffer and everything after. It holds only where the two clocks agree
// (both NTP-synchronised); the first frames, before the camera's first sender report (about 5 s),
// have none.
#pragma once

#include <gst/gst.h>

#include <optional>

namespace jointflow::gst {

/// The lag of @buffer (its PTS in @segment) at @element's clock now, in seconds, clamped at 0 (a
/// source that stamps ahead); nullopt without a clock (not PLAYING) or a PTS in a time segment.
std::optional<double> frameLagSeconds(GstElement* element, const GstSegment& segment,
                                      GstBuffer* buffer);

/// The capture lag of @buffer in seconds (this host's wall clock now minus the camera's time on
/// its "timestamp/x-ntp" or "timestamp/x-unix" reference timestamp meta), clamped at 0; nullopt
/// where the buffer has no such meta.
std::optional<double> captureLagSeconds(GstBuffer* buffer);

}  // namespace jointflow::gst
