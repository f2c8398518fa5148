// Draws lines, circles, rectangles and text straight into a mapped video frame, in the frame's own
// format (packed RGB orders with or without alpha, I420, NV12), so that the overlay needs no
// colour conversion of the whole frame. Colours are given as RGB; for YUV frames they are turned
// into BT.601 Y'CbCr and drawn on each plane at that plane's resolution.
#pragma once

#include <gst/video/video.h>

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace jointflow::gst {

struct Rgb {
  unsigned char r = 0, g = 0, b = 0;
};

/// A well separated, stable colour per track id (golden-ratio steps around the hue circle).
Rgb colourForId(long long id);

class FramePainter {
 public:
  /// @frame must stay mapped (writable) for the painter's lifetime.
  explicit FramePainter(GstVideoFrame* frame);

  void line(cv::Point2f a, cv::Point2f b, Rgb colour, int thickness);
  void polyline(const std::vector<cv::Point2f>& points, Rgb colour, int thickness);
  void circle(cv::Point2f centre, float radius, Rgb colour, bool filled);
  /// A negative @thickness fills the rectangle.
  void rectangle(cv::Point2f top_left, cv::Point2f bottom_right, Rgb colour, int thickness);
  /// Text with its bottom-left corner at @origin, on a filled background box of @background.
  void label(const std::string& text, cv::Point2f origin, Rgb colour, Rgb background,
             double font_scale);

 private:
  struct Plane {
    cv::Mat mat;    ///< view of the plane's pixels (no copy)
    float scale_x;  ///< plane pixels per frame pixel
    float scale_y;
    int component;  ///< -1: packed RGB; 0 = Y, 1 = U, 2 = V; 3 = interleaved UV (NV12)
  };
  cv::Scalar colourOn(const Plane& plane, Rgb colour) const;

  std::vector<Plane> planes_;
  int rgb_offset_[4] = {0, 1, 2, 3};  ///< byte offsets of R, G, B, A within a packed pixel
  int pixel_bytes_ = 3;
};

}  // namespace jointflow::gst
