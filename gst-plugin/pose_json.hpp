// One JSON Lines record per frame, close to DL Streamer's gvametaconvert shape so that tools
// written for it find their way: frame, timestamp, resolution, the camera's source id and per
// person the id, box, score and the keypoints by COCO name. The schema is documented in
// docs/gstreamer.md. jointflowjsonwriter and jointflowmetapublish both serialize through
// FrameRecorder::next(), so a file and a broker get the same bytes for the same frame.
#pragma once

#include <gst/gst.h>
#include <gst/video/video.h>

#include <nlohmann/json.hpp>
#include <string>

#include "jointflowmeta.h"

namespace jointflow::gst {

/// The record of one frame. @meta may be null (a frame without meta has no objects);
/// @width/@height are used when the meta is absent. @timestamp may be GST_CLOCK_TIME_NONE (null).
/// @source_id, when not empty, is written as "source_id" (the camera the frame comes from).
nlohmann::json frameRecord(const GstJointFlowMeta* meta, guint64 frame, GstClockTime timestamp,
                           guint width, guint height, const std::string& source_id = "");

/// The per-stream state both elements keep to serialize frames: the frame counter (from 0 at
/// start), the negotiated frame size (used when a buffer has no meta) and the source id.
class FrameRecorder {
 public:
  /// Back to frame 0 with no known caps (the elements' start()).
  void reset(std::string source_id);
  void setCaps(const GstCaps* caps);
  /// The record of @buffer as one line of compact JSON, without the newline; counts the frame.
  std::string next(GstBuffer* buffer);
  guint64 frames() const { return frame_; }

 private:
  std::string source_id_;
  guint64 frame_ = 0;
  GstVideoInfo info_{};
  bool have_info_ = false;
};

}  // namespace jointflow::gst
