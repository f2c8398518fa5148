#include "jointflow/letterbox.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "jointflow/error.hpp"
#include "jointflow/image_shrink.hpp"

namespace jointflow {

int SizeRule::validAtLeast(int n) const {
  const int k = std::max(1, (std::max(n - plus, 1) + multiple - 1) / multiple);
  return multiple * k + plus;
}

cv::Point2f Letterbox::inputToFrame(cv::Point2f p) const {
  const float sx = static_cast<float>(frame.width) / content.width;
  const float sy = static_cast<float>(frame.height) / content.height;
  return {(p.x - content.x + 0.5f) * sx - 0.5f, (p.y - content.y + 0.5f) * sy - 0.5f};
}

cv::Point2f Letterbox::frameToInput(cv::Point2f p) const {
  const float sx = static_cast<float>(content.width) / frame.width;
  const float sy = static_cast<float>(content.height) / frame.height;
  return {(p.x + 0.5f) * sx - 0.5f + content.x, (p.y + 0.5f) * sy - 0.5f + content.y};
}

GridTransform Letterbox::gridToFrame(float stride) const {
  // frame = (stride * cell - content.x + 0.5) * sx - 0.5, written as cell * scale + offset.
  const float sx = static_cast<float>(frame.width) / content.width;
  const float sy = static_cast<float>(frame.height) / content.height;
  GridTransform t;
  t.scale_x = stride * sx;
  t.scale_y = stride * sy;
  t.offset_x = (0.5f - content.x) * sx - 0.5f;
  t.offset_y = (0.5f - content.y) * sy - 0.5f;
  return t;
}

Letterbox computeLetterbox(cv::Size frame, const InputSize& policy, float scale,
                           const SizeRule& rule) {
  if (frame.width < kMinFrameSide || frame.height < kMinFrameSide) {
    std::ostringstream msg;
    msg << "image of " << frame.width << "x" << frame.height
        << " pixels is too small: the spatial models need at least " << kMinFrameSide << "x"
        << kMinFrameSide;
    throw Error(msg.str());
  }
  if (!(scale > 0.f) || !std::isfinite(scale)) {
    throw Error("inference scale must be a positive number, got " + std::to_string(scale));
  }
  Letterbox box;
  box.frame = frame;
  double factor = scale;
  switch (policy.mode) {
    case InputSize::Mode::kFixed: {
      if (policy.fixed.width < kMinFrameSide || policy.fixed.height < kMinFrameSide) {
        throw Error("fixed input size " + policy.toString() + " is too small");
      }
      box.input = {rule.validAtLeast(static_cast<int>(std::lround(policy.fixed.width * scale))),
                   rule.validAtLeast(static_cast<int>(std::lround(policy.fixed.height * scale)))};
      factor = std::min(static_cast<double>(box.input.width) / frame.width,
                        static_cast<double>(box.input.height) / frame.height);
      break;
    }
    case InputSize::Mode::kNative:
      break;
    case InputSize::Mode::kMaxSide:
      if (policy.max_side < kMinFrameSide) {
        throw Error("maximum input side " + std::to_string(policy.max_side) + " is too small");
      }
      factor *=
          std::min(1.0, static_cast<double>(policy.max_side) / std::max(frame.width, frame.height));
      break;
  }
  const cv::Size size(std::max(1, static_cast<int>(std::lround(frame.width * factor))),
                      std::max(1, static_cast<int>(std::lround(frame.height * factor))));
  if (policy.mode == InputSize::Mode::kFixed) {
    const cv::Size fitted(std::min(size.width, box.input.width),
                          std::min(size.height, box.input.height));
    box.content = cv::Rect((box.input.width - fitted.width) / 2,
                           (box.input.height - fitted.height) / 2, fitted.width, fitted.height);
  } else {
    box.input = {rule.validAtLeast(size.width), rule.validAtLeast(size.height)};
    box.content = cv::Rect(0, 0, size.width, size.height);
  }
  return box;
}

cv::Mat applyLetterbox(const cv::Mat& image, const Letterbox& box) {
  cv::Mat input;
  applyLetterbox(image, box, input);
  return input;
}

void applyLetterbox(const cv::Mat& image, const Letterbox& box, cv::Mat& input) {
  input.create(box.input, image.type());  // keeps input's memory when it has the size
  if (box.content != cv::Rect({0, 0}, box.input)) input.setTo(cv::Scalar::all(0));
  cv::Mat content = input(box.content);
  shrinkImageInto(image, content);
}

}  // namespace jointflow
