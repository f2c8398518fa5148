// A person's box as every output of the plugin gives it: clamped to the frame. The tracker may
// report a box that reaches past the frame (a person at the border, a pose extrapolated while
// coasting); the ROI meta and the JSON records both cut it at the border here, so that they
// always agree.
#pragma once

#include <algorithm>

#include "jointflowmeta.h"

namespace jointflow::gst {

struct FrameBox {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< frame pixels, 0 <= x0 <= x1 <= width (same for y)
};

inline FrameBox boxInFrame(const JointFlowPerson& p, unsigned width, unsigned height) {
  const float w = static_cast<float>(width), h = static_cast<float>(height);
  return {std::clamp(p.x, 0.f, w), std::clamp(p.y, 0.f, h), std::clamp(p.x + p.width, 0.f, w),
          std::clamp(p.y + p.height, 0.f, h)};
}

}  // namespace jointflow::gst
