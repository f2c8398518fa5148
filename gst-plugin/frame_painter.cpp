#include "frame_painter.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace jointflow::gst {
namespace {

// OpenCV draws with sub-pixel precision when points carry this many fractional bits.
constexpr int kShift = 4;
constexpr float kOne = 1 << kShift;

cv::Point fixedPoint(cv::Point2f p, float sx, float sy) {
  return {static_cast<int>(std::lround(p.x * sx * kOne)),
          static_cast<int>(std::lround(p.y * sy * kOne))};
}

int scaledThickness(int thickness, float scale) {
  return std::max(1, static_cast<int>(std::lround(thickness * scale)));
}

// Anti-aliasing blends with the background; on subsampled chroma planes that would only wash the
// colour out, so they get solid edges.
int lineType(float scale) {
  return scale < 1.f ? cv::LINE_8 : cv::LINE_AA;
}

// BT.601 limited range, the colorimetry of the SD and most camera streams.
struct Yuv {
  double y, u, v;
};
Yuv toYuv(Rgb c) {
  return {16 + 0.257 * c.r + 0.504 * c.g + 0.098 * c.b,
          128 - 0.148 * c.r - 0.291 * c.g + 0.439 * c.b,
          128 + 0.439 * c.r - 0.368 * c.g - 0.071 * c.b};
}

}  // namespace

Rgb colourForId(long long id) {
  // Golden-ratio steps around the hue circle keep neighbouring ids far apart in colour; OpenCV's
  // HSV conversion (float: H in degrees, S and V in [0, 1]) does the rest.
  const float hue =
      static_cast<float>(std::fmod(static_cast<double>(id) * 0.6180339887498949, 1.0));
  cv::Mat3f hsv(1, 1, cv::Vec3f(hue * 360.f, 0.85f, 1.f)), rgb;
  cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
  const cv::Vec3f c = rgb(0, 0);
  auto byte = [](float x) { return static_cast<unsigned char>(std::lround(x * 255.f)); };
  return {byte(c[0]), byte(c[1]), byte(c[2])};
}

FramePainter::FramePainter(GstVideoFrame* frame) {
  const GstVideoInfo* info = &frame->info;
  const GstVideoFormat format = GST_VIDEO_INFO_FORMAT(info);
  const int width = GST_VIDEO_INFO_WIDTH(info);
  const int height = GST_VIDEO_INFO_HEIGHT(info);
  auto planeView = [&](int plane, int w, int h, int type) {
    return cv::Mat(h, w, type, GST_VIDEO_FRAME_PLANE_DATA(frame, plane),
                   GST_VIDEO_FRAME_PLANE_STRIDE(frame, plane));
  };
  if (format == GST_VIDEO_FORMAT_I420 || format == GST_VIDEO_FORMAT_NV12) {
    planes_.push_back({planeView(0, width, height, CV_8UC1), 1.f, 1.f, 0});
    const int cw = GST_VIDEO_FRAME_COMP_WIDTH(frame, 1);
    const int ch = GST_VIDEO_FRAME_COMP_HEIGHT(frame, 1);
    const float sx = static_cast<float>(cw) / width, sy = static_cast<float>(ch) / height;
    if (format == GST_VIDEO_FORMAT_I420) {
      planes_.push_back({planeView(1, cw, ch, CV_8UC1), sx, sy, 1});
      planes_.push_back({planeView(2, cw, ch, CV_8UC1), sx, sy, 2});
    } else {
      planes_.push_back({planeView(1, cw, ch, CV_8UC2), sx, sy, 3});
    }
    return;
  }
  pixel_bytes_ = GST_VIDEO_FRAME_COMP_PSTRIDE(frame, 0);
  for (int c = 0; c < 3; ++c) rgb_offset_[c] = GST_VIDEO_FRAME_COMP_OFFSET(frame, c);
  planes_.push_back({planeView(0, width, height, CV_8UC(pixel_bytes_)), 1.f, 1.f, -1});
}

cv::Scalar FramePainter::colourOn(const Plane& plane, Rgb colour) const {
  const Yuv yuv = toYuv(colour);
  switch (plane.component) {
    case 0:
      return cv::Scalar(yuv.y);
    case 1:
      return cv::Scalar(yuv.u);
    case 2:
      return cv::Scalar(yuv.v);
    case 3:
      return cv::Scalar(yuv.u, yuv.v);
    default:
      break;
  }
  // Packed RGB: padding and alpha bytes become 255 (opaque).
  cv::Scalar s(255, 255, 255, 255);
  s[rgb_offset_[0]] = colour.r;
  s[rgb_offset_[1]] = colour.g;
  s[rgb_offset_[2]] = colour.b;
  return s;
}

void FramePainter::line(cv::Point2f a, cv::Point2f b, Rgb colour, int thickness) {
  for (Plane& p : planes_)
    cv::line(p.mat, fixedPoint(a, p.scale_x, p.scale_y), fixedPoint(b, p.scale_x, p.scale_y),
             colourOn(p, colour), scaledThickness(thickness, p.scale_x), lineType(p.scale_x),
             kShift);
}

void FramePainter::polyline(const std::vector<cv::Point2f>& points, Rgb colour, int thickness) {
  for (Plane& p : planes_) {
    std::vector<cv::Point> pts;
    pts.reserve(points.size());
    for (const auto& q : points) pts.push_back(fixedPoint(q, p.scale_x, p.scale_y));
    cv::polylines(p.mat, pts, false, colourOn(p, colour), scaledThickness(thickness, p.scale_x),
                  lineType(p.scale_x), kShift);
  }
}

void FramePainter::circle(cv::Point2f centre, float radius, Rgb colour, bool filled) {
  for (Plane& p : planes_) {
    const int r = static_cast<int>(std::lround(radius * p.scale_x * kOne));
    cv::circle(p.mat, fixedPoint(centre, p.scale_x, p.scale_y), std::max(r, 1), colourOn(p, colour),
               filled ? cv::FILLED : 1, lineType(p.scale_x), kShift);
  }
}

void FramePainter::rectangle(cv::Point2f top_left, cv::Point2f bottom_right, Rgb colour,
                             int thickness) {
  for (Plane& p : planes_)
    cv::rectangle(p.mat, fixedPoint(top_left, p.scale_x, p.scale_y),
                  fixedPoint(bottom_right, p.scale_x, p.scale_y), colourOn(p, colour),
                  thickness < 0 ? cv::FILLED : scaledThickness(thickness, p.scale_x), cv::LINE_8,
                  kShift);
}

void FramePainter::label(const std::string& text, cv::Point2f origin, Rgb colour, Rgb background,
                         double font_scale) {
  int baseline = 0;
  const int thickness = std::max(1, static_cast<int>(std::lround(font_scale * 1.5)));
  const cv::Size size =
      cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font_scale, thickness, &baseline);
  const cv::Point2f pad(3.f, 3.f);
  rectangle(origin + cv::Point2f(-pad.x, pad.y + baseline),
            origin + cv::Point2f(size.width + pad.x, -size.height - pad.y), background, -1);
  for (Plane& p : planes_) {
    // Text is drawn at the plane's resolution; chroma planes get the glyphs' colour at half size.
    const cv::Point org(static_cast<int>(origin.x * p.scale_x),
                        static_cast<int>(origin.y * p.scale_y));
    cv::putText(p.mat, text, org, cv::FONT_HERSHEY_SIMPLEX, font_scale * p.scale_x,
                colourOn(p, colour), scaledThickness(thickness, p.scale_x), lineType(p.scale_x));
  }
}

}  // namespace jointflow::gst
