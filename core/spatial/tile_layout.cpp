// Where the tiles of a frame lie (tiling.hpp).
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "jointflow/error.hpp"
#include "jointflow/tiling.hpp"

namespace jointflow {
namespace {

// Tile origins along an axis of `length` px: the first at 0, the last at length - size, evenly
// between, as few as keep each neighbour's share >= overlap x size.
std::vector<int> origins(int length, int size, float overlap) {
  if (length <= size) return {0};
  const double step = size * (1.0 - overlap);
  // The small slack keeps an exact fit (e.g. 3 tiles of 512 at 0.25 in 1280 px) at its count.
  const int n = 1 + static_cast<int>(std::ceil((length - size) / step - 1e-9));
  std::vector<int> at;
  for (int i = 0; i < n; ++i)
    at.push_back(static_cast<int>(std::lround(static_cast<double>(i) * (length - size) / (n - 1))));
  return at;
}

}  // namespace

std::vector<cv::Rect> tileLayout(cv::Size frame, int size, float overlap) {
  if (size < 1) throw Error("tile size must be >= 1 pixel, got " + std::to_string(size));
  if (!(overlap >= 0.f && overlap <= 0.5f))
    throw Error("tile overlap must be in [0, 0.5], got " + std::to_string(overlap));
  std::vector<cv::Rect> tiles;
  if (frame.width < 1 || frame.height < 1) return tiles;
  const int w = std::min(size, frame.width), h = std::min(size, frame.height);
  for (int y : origins(frame.height, size, overlap))
    for (int x : origins(frame.width, size, overlap)) tiles.emplace_back(x, y, w, h);
  return tiles;
}

int nearestTile(const std::vector<cv::Rect>& tiles, cv::Point2f p) {
  int best = -1;
  std::pair<float, float> best_d{std::numeric_limits<float>::infinity(), 0.f};
  for (size_t i = 0; i < tiles.size(); ++i) {
    const cv::Rect& t = tiles[i];
    // Pixel centres are integers: a tile spans [x - 0.5, x + w - 0.5].
    const float dx = std::abs(p.x - (t.x + 0.5f * (t.width - 1))) / t.width;
    const float dy = std::abs(p.y - (t.y + 0.5f * (t.height - 1))) / t.height;
    // The larger axis distance first; on a tie (tiles of one row, the point nearer to their
    // horizontal borders than to any vertical one) the smaller: the tile of the row nearer in x.
    const std::pair<float, float> d{std::max(dx, dy), std::min(dx, dy)};
    if (d < best_d) best_d = d, best = static_cast<int>(i);
  }
  return best;
}

}  // namespace jointflow
