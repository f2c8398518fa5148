#include "jointflow/image_shrink.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace jointflow {
namespace {

// `image` halved (INTER_AREA) while `size` is at most half of it on both sides.
cv::Mat halveToward(const cv::Mat& image, cv::Size size) {
  cv::Mat step = image;
  while (step.cols >= 2 * size.width && step.rows >= 2 * size.height) {
    cv::Mat half;
    cv::resize(step, half, cv::Size(step.cols / 2, step.rows / 2), 0, 0, cv::INTER_AREA);
    step = half;
  }
  return step;
}

}  // namespace

cv::Mat shrinkImage(const cv::Mat& image, cv::Size size) {
  const cv::Mat step = halveToward(image, size);
  if (step.size() == size) return step;
  cv::Mat out;
  cv::resize(step, out, size, 0, 0, cv::INTER_LINEAR);
  return out;
}

cv::Mat shrinkToSide(const cv::Mat& image, int side) {
  const double shrink = std::max(image.cols, image.rows) / static_cast<double>(side);
  if (shrink <= 1.0) return image.clone();
  const cv::Size size(std::max(1, static_cast<int>(std::lround(image.cols / shrink))),
                      std::max(1, static_cast<int>(std::lround(image.rows / shrink))));
  return shrinkImage(image, size);
}

void shrinkImageInto(const cv::Mat& image, cv::Mat& out) {
  const cv::Mat step = halveToward(image, out.size());
  // Into out's own memory (out may be a region of a larger image): cv::resize and copyTo keep a
  // destination that already has the size and type.
  if (step.size() == out.size())
    step.copyTo(out);
  else
    cv::resize(step, out, out.size(), 0, 0, cv::INTER_LINEAR);
}

}  // namespace jointflow
