// Turns a mapped video frame into the 8-bit 3-channel image the pose networks take, converting
// only what needs converting: packed RGB and BGR frames are wrapped as a cv::Mat view of the
// frame's own pixels (no copy); 4-byte formats lose their padding or alpha byte, and I420/NV12 are
// converted to BGR, into buffers reused from frame to frame.
#pragma once

#include <gst/video/video.h>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow::gst {

class FrameConverter {
 public:
  /// The image and its channel order; valid until the next call and while @frame stays mapped.
  /// Throws jointflow::Error for a format outside JOINTFLOW_VIDEO_FORMATS.
  cv::Mat convert(const GstVideoFrame& frame, PixelOrder* order);

 private:
  cv::Mat yuv_;  ///< planes packed as OpenCV's YUV 4:2:0 conversions expect, when they are not
  cv::Mat bgr_;
};

}  // namespace jointflow::gst
