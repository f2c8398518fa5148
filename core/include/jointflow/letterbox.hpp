// How a frame becomes a network input, and the exact way back.
//
// Coordinates everywhere in JointFlow are continuous pixel coordinates in which integer values
// are pixel centres (OpenCV's convention). The frame is resized to `content.size()` with
// cv::resize, whose sampling maps a destination pixel centre x_d to the source position
// (x_d + 0.5) * frame_w / content_w - 0.5, and placed at `content.tl()` inside an input of size
// `input`, the rest padded with zeros. Every spatial model's output grid then relates to input
// pixels by input = stride * cell (MoveNet: 4, PoseNet: 16, see models/README.md), so that
// frame = Letterbox::gridToFrame(stride).toFrame(cell) holds exactly, per axis.
#pragma once

#include <opencv2/core.hpp>

#include "jointflow/spatial_model.hpp"

namespace jointflow {

/// The input sizes a model accepts: n = multiple * k + plus for some k >= 1
/// (MoveNet: multiple 32, plus 0; PoseNet: multiple 16, plus 1, so that cell i = pixel 16 i).
struct SizeRule {
  int multiple = 32;
  int plus = 0;
  /// Smallest accepted size >= n.
  int validAtLeast(int n) const;
};

struct Letterbox {
  cv::Size frame;    ///< the frame's size
  cv::Size input;    ///< the network input's size
  cv::Rect content;  ///< where the resized frame lies inside the input

  cv::Point2f inputToFrame(cv::Point2f p) const;
  cv::Point2f frameToInput(cv::Point2f p) const;
  /// Grid cell -> frame pixel for an output grid with input = stride * cell.
  GridTransform gridToFrame(float stride) const;
};

/// The smallest frame side the spatial models accept; smaller frames are rejected.
constexpr int kMinFrameSide = 16;

/// Computes the letterbox of a frame under an input size policy at one inference scale
/// (1 = the policy's own size; multi-scale inference multiplies the policy's resize factor).
///   kFixed:   scaled to fit `fixed * scale` (rounded up to the rule), centred, padded;
///   kNative:  resize factor `scale`, padded at the right and bottom to the rule;
///   kMaxSide: resize factor min(1, max_side / longer side) * scale, padded likewise.
/// Throws jointflow::Error for a frame smaller than kMinFrameSide or a nonsensical policy.
Letterbox computeLetterbox(cv::Size frame, const InputSize& policy, float scale,
                           const SizeRule& rule);

/// Resizes (shrinkImage, jointflow/image_shrink.hpp) and pads an 8-bit 3-channel image into the
/// letterbox's input (same pixel order).
cv::Mat applyLetterbox(const cv::Mat& image, const Letterbox& box);

/// applyLetterbox into `input`, reusing its memory when it already has the letterbox's input
/// size and the image's type (a frame after the first).
void applyLetterbox(const cv::Mat& image, const Letterbox& box, cv::Mat& input);

}  // namespace jointflow
