// Shrinking a frame quickly without aliasing: for the network's letterbox and the camera motion
// estimate, which both shrink every frame.
#pragma once

#include <opencv2/core.hpp>

namespace jointflow {

/// `image` resized to `size`. Where `size` is smaller, the image is first halved (INTER_AREA,
/// each output pixel the mean of 2x2) while the target is at most half of it on both sides, and
/// the last step of less than 2x is bilinear (INTER_LINEAR). Why not INTER_AREA all the way:
/// OpenCV's area resize by a fractional factor takes its slow general path, 5 to 15 times the
/// cost of the two steps (768x576 BGR -> 640x480: 11.0 against 1.9 ms of one core; 960x540 grey
/// -> 400x225: 2.7 against 0.2 ms), for a mean difference of 0.4 to 1.3 grey levels. Halving
/// first keeps the bilinear step's shrink under 2x, where it still reads every source pixel, so
/// fine detail does not alias. Both steps keep OpenCV's pixel-centre mapping. Larger targets are
/// bilinear; an image already of `size` is returned as it is (not copied).
/// training/jointflow_train/spatial.py (shrink_image) mirrors this for the networks' inputs.
cv::Mat shrinkImage(const cv::Mat& image, cv::Size size);

/// `image` shrunk with shrinkImage until its longer side is at most `side` px, its aspect kept
/// (each side rounded, at least 1); where it is no larger, a copy of it (callers keep the result
/// past the frame, whose buffer may be reused). The camera motion estimate and the flow of tff's
/// mix work on such frames.
cv::Mat shrinkToSide(const cv::Mat& image, int side);

/// shrinkImage into `out`'s memory, at `out`'s size: `out` (a whole image or a region of one)
/// has the size to shrink to and `image`'s type.
void shrinkImageInto(const cv::Mat& image, cv::Mat& out);

}  // namespace jointflow
