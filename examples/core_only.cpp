// The core library alone, without GStreamer: jointflow::Tracker on the frames of a video read
// with OpenCV, printing each frame's tracks.
//
//   build/examples/core_only VIDEO [MAX_FRAMES]
#include <cstdio>
#include <cstdlib>

#include <opencv2/videoio.hpp>

#include "jointflow/error.hpp"
#include "jointflow/tracker.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s VIDEO [MAX_FRAMES]\n", argv[0]);
    return 2;
  }
  const long max_frames = argc > 2 ? std::strtol(argv[2], nullptr, 10) : 20;
  try {
    jointflow::TrackerSettings settings;  // shipped MoveNet model, similarity auto
    jointflow::Tracker tracker(settings);
    cv::VideoCapture video(argv[1]);
    if (!video.isOpened()) throw jointflow::Error(std::string(argv[1]) + ": cannot open video");
    cv::Mat frame;  // OpenCV decodes to BGR
    for (long n = 0; n < max_frames && video.read(frame); ++n) {
      const auto tracks = tracker.process(frame, jointflow::PixelOrder::kBGR);
      std::printf("frame %ld: %zu people\n", n, tracks.size());
      for (const auto& t : tracks) {
        const auto& hip = t.pose.keypoints[jointflow::kLeftHip];
        std::printf("  track %lld%s score %.2f left_hip %.0f,%.0f (%.2f)\n",
                    static_cast<long long>(t.track_id), t.tentative ? " (tentative)" : "",
                    t.pose.score, hip.x, hip.y, hip.score);
      }
    }
  } catch (const jointflow::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
