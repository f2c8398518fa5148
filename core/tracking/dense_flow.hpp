// Dense optical flow between two grey frames: OpenCV's DIS, preset medium (the "flow"
// similarity, and the flow of tff's mix).
#pragma once

#include <opencv2/video/tracking.hpp>

namespace jointflow {

/// DIS with a new instance per frame size and a fresh output per call. Why: in a standalone
/// program OpenCV 4.6's DIS crashed (a null read) on 768x576 frames after one instance had run
/// twice into one output matrix on 480x360 frames, as a resolution change mid-stream gives it;
/// either precaution alone avoided it.
class DenseFlow {
 public:
  /// CV_32FC2 flow from -> to, in pixels of the frames (both 8-bit grey, one size).
  cv::Mat operator()(const cv::Mat& from, const cv::Mat& to) {
    if (!dis_ || from.size() != size_) {
      dis_ = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
      size_ = from.size();
    }
    cv::Mat flow;
    dis_->calc(from, to, flow);
    return flow;
  }

 private:
  cv::Ptr<cv::DISOpticalFlow> dis_;
  cv::Size size_;
};

}  // namespace jointflow
