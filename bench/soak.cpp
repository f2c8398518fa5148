// soak: a long run of jointflowtrack, for leaks and memory growth (issue 7).
//
// Frames of vtest.avi (decoded once, scaled to --width, played forwards then backwards so the
// people walk on without a cut) are pushed through
//   appsrc ! jointflowtrack ! jointflowoverlay ! jointflowjsonwriter ! fakesink
// as fast as the element takes them. Every --every frames the process's resident memory (VmRSS)
// is written to --csv. Built in the sanitizer build (make test-asan's build-asan) the same run is
// a leak check: LeakSanitizer reports anything not freed at exit and the exit status is non-zero.
//
//   soak [--frames 10000] [--every 100] [--width 192] [--csv rss.csv] [--similarity oks]
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <CLI/CLI.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "resident_memory.hpp"

namespace {

/// Resident set size of this process in KiB (Linux /proc), -1 when unknown.

std::vector<cv::Mat> loadFrames(const std::string& video, int width, int count) {
  cv::VideoCapture capture(video);
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  while (static_cast<int>(frames.size()) < count && capture.read(frame)) {
    cv::Mat small;
    const int height = (frame.rows * width / frame.cols) & ~1;
    cv::resize(frame, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    frames.push_back(small);
  }
  return frames;
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"Long run of jointflowtrack: resident memory over time, leaks under ASan"};
  std::string video = JOINTFLOW_VTEST_AVI, csv, similarity = "oks", tff_model;
  int frames = 10000, every = 100, width = 192, clip = 200;
  app.add_option("--video", video, "video file (default: opencv-doc's vtest.avi)");
  app.add_option("--frames", frames, "frames to push")->check(CLI::Range(1, 10000000));
  app.add_option("--every", every, "frames between two memory samples")->check(CLI::PositiveNumber);
  app.add_option("--width", width, "frame width (height keeps the aspect)")
      ->check(CLI::Range(16, 4096));
  app.add_option("--clip", clip, "frames of the video played back and forth")
      ->check(CLI::Range(2, 100000));
  app.add_option("--csv", csv, "file for 'frame,rss_kib,seconds' lines (empty: stdout only)");
  app.add_option("--similarity", similarity,
                 "jointflowtrack similarity (oks, tff, iou, pckh, flow)");
  app.add_option("--tff-model", tff_model, "jointflowtrack tff-model (for --similarity tff)");
  CLI11_PARSE(app, argc, argv);

  const std::vector<cv::Mat> images = loadFrames(video, width, clip);
  if (images.size() < 2) {
    std::cerr << "soak: cannot read 2 frames of " << video << "\n";
    return 2;
  }
  const int w = images[0].cols, h = images[0].rows;
  const std::string launch =
      "appsrc name=src is-live=false format=time block=true max-bytes=0 max-buffers=4 "
      "caps=video/x-raw,format=BGR,width=" +
      std::to_string(w) + ",height=" + std::to_string(h) +
      ",framerate=30/1 ! jointflowtrack input-size=native similarity=" + similarity +
      (tff_model.empty() ? "" : " tff-model=" + tff_model) +
      " ! jointflowoverlay ! jointflowjsonwriter location=/dev/null ! fakesink sync=false";
  GError* error = nullptr;
  GstElement* pipeline = gst_parse_launch(launch.c_str(), &error);
  if (!pipeline) {
    std::cerr << "soak: " << (error ? error->message : "cannot build the pipeline") << "\n";
    g_clear_error(&error);
    return 2;
  }
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    std::cerr << "soak: the pipeline does not start (models?)\n";
    return 2;
  }

  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    out << "frame,rss_kib,seconds\n";
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto sample = [&](int frame) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const long rss = jointflow::bench::residentKiB();
    std::cout << "frame " << frame << " rss " << rss << " KiB " << s << " s" << std::endl;
    if (out) out << frame << "," << rss << "," << s << "\n" << std::flush;
  };
  const int period = 2 * static_cast<int>(images.size()) - 2;  // forwards, then backwards
  for (int i = 0; i < frames; ++i) {
    const int k = i % period;
    const cv::Mat& img = images[k < static_cast<int>(images.size()) ? k : period - k];
    const size_t bytes = img.total() * img.elemSize();
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, bytes, nullptr);
    gst_buffer_fill(buffer, 0, img.data, bytes);
    GST_BUFFER_PTS(buffer) = gst_util_uint64_scale(i, GST_SECOND, 30);
    GST_BUFFER_DURATION(buffer) = GST_SECOND / 30;
    if (gst_app_src_push_buffer(GST_APP_SRC(src), buffer) != GST_FLOW_OK) {
      std::cerr << "soak: the pipeline stopped at frame " << i << "\n";
      break;
    }
    if (i % every == 0) sample(i);
  }
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_timed_pop_filtered(
      bus, GST_CLOCK_TIME_NONE, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  int status = 0;
  if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
    gst_message_parse_error(msg, &error, nullptr);
    std::cerr << "soak: " << error->message << "\n";
    g_clear_error(&error);
    status = 1;
  }
  sample(frames);
  gst_message_unref(msg);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(pipeline);
  gst_deinit();  // so that LeakSanitizer sees only what was really leaked
  return status;
}
