// A live frame's lag: how long ago it was captured, on the pipeline clock. A live source stamps
// each frame with the clock's running time at which it captured it (v4l2src) or received it
// (rtspsrc's jitter buffer, from the packets' arrival); the clock's running time now, less that,
// is the frame's age: decoding, queues, conversion and inference count, the camera's encoder and
// the network before the receiver do not. jointflowtrack's lag histogram and jointflow-track's
// --output-lag measure it the same way, here.
#pragma once

#include <gst/gst.h>

#include <optional>

namespace jointflow::gst {

/// The lag of @buffer (its PTS in @segment) at @element's clock now, in seconds, clamped at 0 (a
/// source that stamps ahead); nullopt without a clock (not PLAYING) or a PTS in a time segment.
std::optional<double> frameLagSeconds(GstElement* element, const GstSegment& segment,
                                      GstBuffer* buffer);

}  // namespace jointflow::gst
