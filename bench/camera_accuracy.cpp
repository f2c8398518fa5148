#include "camera_accuracy.hpp"

#include <opencv2/imgproc.hpp>

#include "../core/tracking/camera_motion.hpp"
#include "cpu_time.hpp"

namespace jointflow::bench {
namespace {

cv::Matx33d homogeneous(const cv::Matx23d& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), 0, 0, 1};
}

/// The people of a ground-truth frame as boxes around their joints, a fifth of the height wider
/// on every side (the joints do not reach the edge of a person).
std::vector<Box> peopleBoxes(const posetrack::Frame& frame) {
  std::vector<Box> out;
  for (const posetrack::Person& p : frame.people) {
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (const auto& j : p.joints) {
      if (!j) continue;
      x0 = std::min(x0, j->x), y0 = std::min(y0, j->y);
      x1 = std::max(x1, j->x), y1 = std::max(y1, j->y);
    }
    if (x1 < x0) continue;
    const double pad = 0.2 * (y1 - y0) + 10.0;
    out.push_back({static_cast<float>(x0 - pad), static_cast<float>(y0 - pad),
                   static_cast<float>(x1 - x0 + 2 * pad), static_cast<float>(y1 - y0 + 2 * pad)});
  }
  return out;
}

}  // namespace

CameraAccuracy measureCameraEstimate(const std::vector<cv::Mat>& images,
                                     const posetrack::Sequence& ground_truth,
                                     const Variant& variant) {
  const OneOpenCvThread one_thread;
  CameraAccuracy out;
  CameraMotionTracker tracker;
  std::vector<Box> previous_people;
  for (size_t k = 0; k < variant.frames.size(); ++k) {
    const FrameRecipe& r = variant.frames[k];
    cv::Mat grey;
    cv::cvtColor(renderFrame(images[static_cast<size_t>(r.source)], r, variant.size), grey,
                 cv::COLOR_BGR2GRAY);
    std::vector<Box> people = peopleBoxes(ground_truth.frames[k]);
    std::vector<Box> exclude = people;
    exclude.insert(exclude.end(), previous_people.begin(), previous_people.end());
    const double t0 = threadCpuMs();
    const cv::Matx23f estimate = tracker.update(grey, exclude);
    const double t1 = threadCpuMs();
    previous_people = std::move(people);
    if (k == 0) continue;
    out.update_ms.push_back(t1 - t0);
    const cv::Matx33d truth = homogeneous(r.warp) * homogeneous(variant.frames[k - 1].warp).inv();
    double sum = 0.0;
    for (int gy = 0; gy < 5; ++gy)
      for (int gx = 0; gx < 5; ++gx) {
        const cv::Point2f p(static_cast<float>(variant.size.width * (gx + 0.5) / 5),
                            static_cast<float>(variant.size.height * (gy + 0.5) / 5));
        const cv::Point2f e = applyMotion(estimate, p);
        const cv::Vec3d t = truth * cv::Vec3d(p.x, p.y, 1.0);
        sum += std::hypot(e.x - t[0], e.y - t[1]);
      }
    out.error_px.push_back(sum / 25.0);
  }
  return out;
}

}  // namespace jointflow::bench
