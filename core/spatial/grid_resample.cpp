#include "jointflow/grid_resample.hpp"

#include <opencv2/imgproc.hpp>

#include "tensor.hpp"

namespace jointflow {

cv::Mat resampleToGrid(const cv::Mat& tensor, const GridTransform& from, const GridTransform& to,
                       cv::Size to_size, const std::vector<DisplacementChannels>& displacements) {
  detail::checkTensor(tensor, "resampled tensor", -1, 1, {});
  const int c = detail::channels(tensor);
  cv::Mat out(std::vector<int>{1, c, to_size.height, to_size.width}, CV_32F);
  // Destination cell (u, v) -> frame -> source cell: src = (dst * to.scale + to.offset -
  // from.offset) / from.scale, an axis-aligned affine map given to warpAffine as the inverse map.
  const cv::Matx23d src_of_dst(
      to.scale_x / from.scale_x, 0, (to.offset_x - from.offset_x) / from.scale_x, 0,
      to.scale_y / from.scale_y, (to.offset_y - from.offset_y) / from.scale_y);
  for (int ch = 0; ch < c; ++ch) {
    cv::Mat dst = detail::plane(out, ch);
    cv::warpAffine(detail::plane(tensor, ch), dst, src_of_dst, to_size,
                   cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  }
  const double rx = from.scale_x / to.scale_x, ry = from.scale_y / to.scale_y;
  for (const auto& d : displacements) {
    if (d.x_channel >= 0) detail::plane(out, d.x_channel) *= rx;
    if (d.y_channel >= 0) detail::plane(out, d.y_channel) *= ry;
  }
  return out;
}

}  // namespace jointflow
