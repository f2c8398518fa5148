// One JSON Lines record per frame, close to DL Streamer's gvametaconvert shape so that tools
// written for it find their way: frame, timestamp, resolution and per person the id, box, score
// and the keypoints by COCO name. The schema is documented in docs/gstreamer.md.
#pragma once

#include <gst/gst.h>

#include <nlohmann/json.hpp>

#include "jointflowmeta.h"

namespace jointflow::gst {

/// The record of one frame. @meta may be null (a frame without meta has no objects);
/// @width/@height are used when the meta is absent. @timestamp may be GST_CLOCK_TIME_NONE (null).
nlohmann::json frameRecord(const GstJointFlowMeta* meta, guint64 frame, GstClockTime timestamp,
                           guint width, guint height);

}  // namespace jointflow::gst
