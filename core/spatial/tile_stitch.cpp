// The maps of a frame's tiles on one grid over the frame (tiling.hpp).
#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "jointflow/tiling.hpp"
#include "tensor.hpp"

namespace jointflow {

cv::Mat stitchTileMaps(const std::vector<cv::Mat>& maps, const std::vector<GridTransform>& grids,
                       const std::vector<cv::Rect>& tiles, const GridTransform& to, cv::Size size) {
  if (maps.empty() || maps.size() != grids.size() || maps.size() != tiles.size())
    throw Error("stitchTileMaps: expected one map and one grid per tile, and at least one tile");
  for (const cv::Mat& m : maps) detail::checkTensor(m, "stitched tile map", -1, 1, {});
  const int c = detail::channels(maps.front());
  // Which tile each cell of the frame grid takes.
  cv::Mat owner(size, CV_32S);
  for (int r = 0; r < size.height; ++r)
    for (int col = 0; col < size.width; ++col)
      owner.at<int>(r, col) = nearestTile(tiles, to.toFrame({float(col), float(r)}));
  cv::Mat out(std::vector<int>{1, c, size.height, size.width}, CV_32F, cv::Scalar(0));
  for (size_t i = 0; i < tiles.size(); ++i) {
    const cv::Mat mine = owner == static_cast<int>(i);
    const cv::Rect roi = cv::boundingRect(mine);
    if (roi.empty()) continue;
    if (detail::channels(maps[i]) != c)
      throw Error("stitchTileMaps: the tiles' maps have different channel counts");
    // Destination cell (u, v) of the ROI -> frame -> the tile's cell, as resampleToGrid maps it.
    const GridTransform& from = grids[i];
    const cv::Matx23d src_of_dst(
        to.scale_x / from.scale_x, 0,
        ((roi.x * to.scale_x + to.offset_x) - from.offset_x) / from.scale_x, 0,
        to.scale_y / from.scale_y,
        ((roi.y * to.scale_y + to.offset_y) - from.offset_y) / from.scale_y);
    cv::Mat sampled;
    for (int ch = 0; ch < c; ++ch) {
      cv::warpAffine(detail::plane(maps[i], ch), sampled, src_of_dst, roi.size(),
                     cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
      cv::Mat dst = detail::plane(out, ch)(roi);
      sampled.copyTo(dst, mine(roi));
    }
  }
  return out;
}

}  // namespace jointflow
