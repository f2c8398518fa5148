#include "tensor.hpp"

#include <sstream>

#include "jointflow/error.hpp"

namespace jointflow::detail {

void checkTensor(const cv::Mat& t, const std::string& what, int exact_channels, int min_channels,
                 cv::Size grid) {
  std::ostringstream msg;
  if (t.empty() || t.dims != 4 || t.type() != CV_32F || t.size[0] != 1 || !t.isContinuous()) {
    msg << what << ": expected a continuous CV_32F tensor {1, C, H, W}, got dims=" << t.dims
        << " type=" << t.type();
    throw Error(msg.str());
  }
  const int c = t.size[1];
  if ((exact_channels >= 0 && c != exact_channels) || c < min_channels) {
    msg << what << ": expected " << (exact_channels >= 0 ? exact_channels : min_channels)
        << (exact_channels >= 0 ? "" : " or more") << " channels, got " << c;
    throw Error(msg.str());
  }
  if (!grid.empty() && (t.size[2] != grid.height || t.size[3] != grid.width)) {
    msg << what << ": expected a " << grid.height << "x" << grid.width << " grid, got " << t.size[2]
        << "x" << t.size[3];
    throw Error(msg.str());
  }
}

}  // namespace jointflow::detail
