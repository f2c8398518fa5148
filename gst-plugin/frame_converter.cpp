#include "frame_converter.hpp"

#include <algorithm>
#include <cstring>

#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"

namespace jointflow::gst {
namespace {

cv::Mat planeView(const GstVideoFrame& frame, int plane, int width, int height, int type) {
  return cv::Mat(height, width, type, GST_VIDEO_FRAME_PLANE_DATA(&frame, plane),
                 GST_VIDEO_FRAME_PLANE_STRIDE(&frame, plane));
}

// Copies @rows rows of @width bytes to a destination with @dst_width bytes per row, repeating the
// last column (and row) where the destination is larger: OpenCV's 4:2:0 conversions need even
// sizes, GStreamer allows odd ones.
void copyPlane(const guint8* src, int src_stride, int width, int rows, guint8* dst, int dst_width,
               int dst_rows, int bytes_per_pixel) {
  for (int r = 0; r < dst_rows; ++r) {
    const guint8* s = src + static_cast<size_t>(std::min(r, rows - 1)) * src_stride;
    guint8* d = dst + static_cast<size_t>(r) * dst_width;
    std::memcpy(d, s, width);
    for (int c = width; c < dst_width; c += bytes_per_pixel)
      std::memcpy(d + c, s + width - bytes_per_pixel, bytes_per_pixel);
  }
}

// True when the planes already lie one after the other without padding, as OpenCV expects.
bool contiguous420(const GstVideoFrame& frame, int n_planes) {
  const int w = GST_VIDEO_FRAME_WIDTH(&frame), h = GST_VIDEO_FRAME_HEIGHT(&frame);
  if (w % 2 || h % 2) return false;
  const auto* y = static_cast<const guint8*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
  if (GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0) != w) return false;
  const guint8* expected = y + static_cast<size_t>(w) * h;
  const int chroma_stride = n_planes == 3 ? w / 2 : w;
  for (int p = 1; p < n_planes; ++p) {
    if (GST_VIDEO_FRAME_PLANE_DATA(&frame, p) != expected) return false;
    if (GST_VIDEO_FRAME_PLANE_STRIDE(&frame, p) != chroma_stride) return false;
    expected += static_cast<size_t>(chroma_stride) * (h / 2);
  }
  return true;
}

}  // namespace

cv::Mat FrameConverter::convert(const GstVideoFrame& frame, PixelOrder* order) {
  const int w = GST_VIDEO_FRAME_WIDTH(&frame), h = GST_VIDEO_FRAME_HEIGHT(&frame);
  const GstVideoFormat format = GST_VIDEO_FRAME_FORMAT(&frame);
  switch (format) {
    case GST_VIDEO_FORMAT_BGR:
    case GST_VIDEO_FORMAT_RGB:
      *order = format == GST_VIDEO_FORMAT_RGB ? PixelOrder::kRGB : PixelOrder::kBGR;
      return planeView(frame, 0, w, h, CV_8UC3);
    case GST_VIDEO_FORMAT_BGRx:
    case GST_VIDEO_FORMAT_BGRA:
    case GST_VIDEO_FORMAT_RGBx:
    case GST_VIDEO_FORMAT_RGBA:
      // Dropping the fourth byte keeps the order of the other three.
      cv::cvtColor(planeView(frame, 0, w, h, CV_8UC4), bgr_, cv::COLOR_BGRA2BGR);
      *order = (format == GST_VIDEO_FORMAT_RGBx || format == GST_VIDEO_FORMAT_RGBA)
                   ? PixelOrder::kRGB
                   : PixelOrder::kBGR;
      return bgr_;
    case GST_VIDEO_FORMAT_xRGB:
    case GST_VIDEO_FORMAT_xBGR: {
      bgr_.create(h, w, CV_8UC3);
      const int from_to[] = {1, 0, 2, 1, 3, 2};
      const cv::Mat src = planeView(frame, 0, w, h, CV_8UC4);
      cv::mixChannels(&src, 1, &bgr_, 1, from_to, 3);
      *order = format == GST_VIDEO_FORMAT_xRGB ? PixelOrder::kRGB : PixelOrder::kBGR;
      return bgr_;
    }
    case GST_VIDEO_FORMAT_I420:
    case GST_VIDEO_FORMAT_NV12: {
      const bool i420 = format == GST_VIDEO_FORMAT_I420;
      const int n_planes = i420 ? 3 : 2;
      const int w2 = w + (w & 1), h2 = h + (h & 1);
      cv::Mat packed;
      if (contiguous420(frame, n_planes)) {
        packed = cv::Mat(h * 3 / 2, w, CV_8UC1, GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
      } else {
        yuv_.create(h2 * 3 / 2, w2, CV_8UC1);
        guint8* dst = yuv_.data;
        copyPlane(static_cast<const guint8*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0)),
                  GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0), w, h, dst, w2, h2, 1);
        dst += static_cast<size_t>(w2) * h2;
        const int cw = GST_VIDEO_FRAME_COMP_WIDTH(&frame, 1);  // (w + 1) / 2
        const int ch = GST_VIDEO_FRAME_COMP_HEIGHT(&frame, 1);
        for (int p = 1; p < n_planes; ++p) {
          const int row_bytes = i420 ? cw : 2 * cw;
          copyPlane(static_cast<const guint8*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, p)),
                    GST_VIDEO_FRAME_PLANE_STRIDE(&frame, p), row_bytes, ch, dst, row_bytes, h2 / 2,
                    i420 ? 1 : 2);
          dst += static_cast<size_t>(row_bytes) * (h2 / 2);
        }
        packed = yuv_;
      }
      cv::cvtColor(packed, bgr_, i420 ? cv::COLOR_YUV2BGR_I420 : cv::COLOR_YUV2BGR_NV12);
      *order = PixelOrder::kBGR;
      return bgr_(cv::Rect(0, 0, w, h));
    }
    default:
      throw Error(std::string("jointflowtrack: unsupported video format ") +
                  gst_video_format_to_string(format) +
                  " (expected one of RGB, BGR, RGBx, BGRx, "
                  "xRGB, xBGR, RGBA, BGRA, I420, NV12)");
  }
}

}  // namespace jointflow::gst
