#include "jointflow/image_shrink.hpp"

#include <opencv2/imgproc.hpp>

namespace jointflow {

cv::Mat shrinkImage(const cv::Mat& image, cv::Size size) {
  if (image.size() == size) return image;
  cv::Mat step = image;
  while (step.cols >= 2 * size.width && step.rows >= 2 * size.height) {
    cv::Mat half;
    cv::resize(step, half, cv::Size(step.cols / 2, step.rows / 2), 0, 0, cv::INTER_AREA);
    step = half;
  }
  if (step.size() == size) return step;
  cv::Mat out;
  cv::resize(step, out, size, 0, 0, cv::INTER_LINEAR);
  return out;
}

}  // namespace jointflow
