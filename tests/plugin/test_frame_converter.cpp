// FrameConverter: every accepted format reaches the networks as the same 3-channel image (up to
// the loss of YUV 4:2:0), with views instead of copies where the format allows.
#include <catch2/catch.hpp>

#include <opencv2/imgproc.hpp>

#include "frame_converter.hpp"
#include "gst_test_util.hpp"

using namespace jointflow::test;

namespace {

// A smooth colour image (4:2:0 keeps it well) of an odd size, which YUV conversions must handle.
cv::Mat referenceBgr(int width, int height) {
  cv::Mat bgr(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      bgr.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<uchar>(40 + 3 * x), static_cast<uchar>(60 + 2 * y),
                    static_cast<uchar>(200 - x - y));
  return bgr;
}

// The reference image in @format, converted by GStreamer's videoconvert.
GstBuffer* inFormat(const cv::Mat& bgr, const std::string& format) {
  GstHarness* h = gst_harness_new_parse(
      ("videoconvert ! capsfilter caps=video/x-raw,format=" + format).c_str());
  gst_harness_set_src_caps_str(h, capsFor("BGR", bgr.cols, bgr.rows).c_str());
  GstVideoInfo info;
  gst_video_info_set_format(&info, GST_VIDEO_FORMAT_BGR, bgr.cols, bgr.rows);
  GstBuffer* in = gst_buffer_new_allocate(nullptr, GST_VIDEO_INFO_SIZE(&info), nullptr);
  GstVideoFrame frame;
  gst_video_frame_map(&frame, &info, in, GST_MAP_WRITE);
  for (int y = 0; y < bgr.rows; ++y)
    memcpy(static_cast<guint8*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0)) +
               y * GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0),
           bgr.ptr(y), bgr.cols * 3);
  gst_video_frame_unmap(&frame);
  REQUIRE(gst_harness_push(h, in) == GST_FLOW_OK);
  GstBuffer* out = gst_harness_pull(h);
  gst_harness_teardown(h);
  return out;
}

}  // namespace

TEST_CASE("frames of every format convert to the network image", "[plugin][convert]") {
  initGst();
  const auto format = GENERATE(as<std::string>{}, "RGB", "BGR", "RGBx", "BGRx", "xRGB", "xBGR",
                               "RGBA", "BGRA", "I420", "NV12");
  const auto size = GENERATE(cv::Size(64, 48), cv::Size(37, 23));
  INFO("format " << format << " size " << size);
  const cv::Mat reference = referenceBgr(size.width, size.height);
  GstBuffer* buffer = inFormat(reference, format);
  GstVideoInfo info;
  gst_video_info_set_format(&info, gst_video_format_from_string(format.c_str()), size.width,
                            size.height);
  GstVideoFrame frame;
  REQUIRE(gst_video_frame_map(&frame, &info, buffer, GST_MAP_READ));

  jointflow::gst::FrameConverter converter;
  jointflow::PixelOrder order;
  cv::Mat image = converter.convert(frame, &order);
  REQUIRE(image.type() == CV_8UC3);
  REQUIRE(image.size() == size);
  if (format == "RGB" || format == "BGR")  // a view of the frame, not a copy
    CHECK(image.data == GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
  cv::Mat bgr = image;
  if (order == jointflow::PixelOrder::kRGB) cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
  cv::Mat diff;
  cv::absdiff(bgr, reference, diff);
  double max_diff = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff);
  const bool yuv = format == "I420" || format == "NV12";
  CHECK(max_diff <= (yuv ? 24 : 0));
  if (yuv) CHECK(cv::mean(diff)[0] < 4.0);

  gst_video_frame_unmap(&frame);
  gst_buffer_unref(buffer);
}
