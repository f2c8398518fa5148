// Tiled inference (SpatialOptions::tiles): where the tiles lie, and how the poses of their network
// runs become the poses of the frame.
//
// Layout: square tiles of `size` frame pixels in rows and columns; along each axis the first tile
// starts at 0, the last ends at the frame's border, and those between are spread evenly, as few as
// keep every neighbour's share at least `overlap` x size. An axis no longer than `size` is one
// tile of the axis's length. All tiles of a frame have one size, so the network meets one input
// shape (OpenVINO compiles each shape it meets).
//
// Merge: each run's poses are in frame pixels. A pose whose box reaches within two grid cells of
// a border of its tile that lies inside the frame is "cut": the tile saw part of the person. Poses
// are taken whole ones first (highest score first), then cut ones (the centre of their box
// furthest from their tile's inner borders first: the most of the person in view). A pose is
// dropped as a second view of one already taken from another run when at least half of the
// smaller box lies in the other box and
//   - most joints both hold lie where the other has them (OKS's term >= 0.5 on the larger box's
//     scale): the same person seen twice, or
//   - it is a part of the other: its box at most part_area of the other's and part_inside in it,
//     with at least two joints in place or none held in common. A tile that sees only a person's
//     legs, or a hand, decodes them as a person whose other joints lie anywhere.
// Poses of one run are never compared: the decoder already told its people apart. A cut pose that
// no other run saw too is dropped: another run saw that place whole and found nobody. Last, boxes
// and keypoints are clipped to the frame.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"
#include "jointflow/types.hpp"

namespace jointflow {

/// The tiles of a frame, row by row, left to right. Throws jointflow::Error for a size < 1 or an
/// overlap outside [0, 0.5].
std::vector<cv::Rect> tileLayout(cv::Size frame, int size, float overlap);

/// The poses of one network run on part of the frame, in frame pixels.
struct TileRun {
  cv::Rect view;     ///< the part of the frame the run saw (the whole frame: its full-frame pass)
  float cell = 4.f;  ///< one cell of the run's output grid, in frame pixels
  Poses poses;
};

/// Least distance, frame pixels, from the box to a border of `view` that lies inside the frame
/// (negative where the box reaches past it); +infinity when no border of the view does.
float innerBorderMargin(const Box& box, const cv::Rect& view, cv::Size frame);

struct TileMergeOptions {
  float part_area = 0.6f;        ///< a part's box is at most this share of the whole's
  float part_inside = 0.8f;      ///< and lies at least this share in it
  float joint_threshold = 0.3f;  ///< keypoints that count in the agreement
  int max_persons = 100;
};

/// The poses of the frame from those of its runs, highest score first, at most max_persons.
Poses mergeTileRuns(const std::vector<TileRun>& runs, cv::Size frame,
                    const TileMergeOptions& options);

/// The index of the tile whose centre is nearest to `p` (the larger of the two axis distances,
/// relative to the tile's side; on a tie the smaller one): among equal tiles the one where p lies
/// furthest from the borders. -1 for no tiles.
int nearestTile(const std::vector<cv::Rect>& tiles, cv::Point2f p);

/// The maps of the tiles' runs ({1, C, h, w} each, C alike; `grids` maps each to the frame) on
/// one grid over the frame: cell (column, row) of `to`, a grid of `size`, takes the value of the
/// tile whose centre is nearest (nearestTile), sampled bilinearly at the cell's frame position
/// (the nearest border value outside the tile's grid). For the TFF network and re-identification
/// where no run saw the whole frame.
cv::Mat stitchTileMaps(const std::vector<cv::Mat>& maps, const std::vector<GridTransform>& grids,
                       const std::vector<cv::Rect>& tiles, const GridTransform& to, cv::Size size);

}  // namespace jointflow
