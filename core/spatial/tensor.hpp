// Internal helpers for the {1, C, H, W} CV_32F tensors that cv::dnn returns.
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace jointflow::detail {

inline int channels(const cv::Mat& t) {
  return t.size[1];
}
inline int rows(const cv::Mat& t) {
  return t.size[2];
}
inline int cols(const cv::Mat& t) {
  return t.size[3];
}

/// Channel c of a {1, C, H, W} tensor as an H x W matrix header (no copy).
inline cv::Mat plane(const cv::Mat& t, int c) {
  return cv::Mat(t.size[2], t.size[3], CV_32F, const_cast<float*>(t.ptr<float>(0, c)));
}

/// Throws jointflow::Error unless `t` is a CV_32F {1, C, H, W} tensor with C >= min_channels
/// (exactly `exact_channels` when that is >= 0) and, when grid is non-empty, H x W = grid.
void checkTensor(const cv::Mat& t, const std::string& what, int exact_channels, int min_channels,
                 cv::Size grid);

}  // namespace jointflow::detail
