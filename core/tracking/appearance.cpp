// Appearance descriptors for re-identification (appearance.hpp).
#include "appearance.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace jointflow {
namespace {

void normalise(std::vector<float>& v) {
  double n = 0;
  for (float x : v) n += static_cast<double>(x) * x;
  if (n <= 0) {
    v.clear();
    return;
  }
  const float inv = static_cast<float>(1.0 / std::sqrt(n));
  for (float& x : v) x *= inv;
}

// Mean feature vector over the detected keypoints, read with the association's bilinear sampler.
std::vector<float> pooledFeatures(const Pose& pose, const cv::Mat& features,
                                  const GridTransform& grid, const JointThresholds& thresholds) {
  if (features.empty() || features.dims != 4 || features.type() != CV_32F) return {};
  const cv::Mat f = features.isContinuous() ? features : features.clone();
  const int channels = f.size[1];
  std::vector<float> sum(channels, 0.f);
  int n = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& k = pose.keypoints[j];
    if (!isDetected(k, thresholds[j])) continue;
    const cv::Point2f g = grid.toGrid({k.x, k.y});
    for (int c = 0; c < channels; ++c) sum[c] += sampleBilinear(f, c, g);
    ++n;
  }
  if (n == 0) return {};
  normalise(sum);
  return sum;
}

// 16 hue x 4 saturation bins over the pixels of the box that are neither dark nor grey (their
// hue says nothing), normalised.
std::vector<float> colourHistogram(const Pose& pose, const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) return {};
  const cv::Rect box =
      cv::Rect(cv::Point(static_cast<int>(pose.box.x), static_cast<int>(pose.box.y)),
               cv::Size(static_cast<int>(pose.box.w), static_cast<int>(pose.box.h))) &
      cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (box.area() < 4) return {};
  cv::Mat hsv, mask;
  cv::cvtColor(bgr(box), hsv, cv::COLOR_BGR2HSV);
  cv::inRange(hsv, cv::Scalar(0, 40, 40), cv::Scalar(180, 256, 256), mask);
  const int channels[] = {0, 1};
  const int bins[] = {16, 4};
  const float hue[] = {0, 180}, sat[] = {40, 256};
  const float* ranges[] = {hue, sat};
  cv::Mat hist;
  cv::calcHist(&hsv, 1, channels, mask, hist, 2, bins, ranges);
  std::vector<float> v(hist.begin<float>(), hist.end<float>());
  normalise(v);
  return v;
}

}  // namespace

Descriptor describeAppearance(const Pose& pose, const cv::Mat& features,
                              const GridTransform& grid_to_frame, const cv::Mat& bgr,
                              const JointThresholds& thresholds, AppearanceModel model) {
  if (model == AppearanceModel::kOff) return {};
  Descriptor d = pooledFeatures(pose, features, grid_to_frame, thresholds);
  if (model != AppearanceModel::kFeaturesColour || d.empty()) return d;
  // Both parts normalised, so the similarity is the mean of the two cosines.
  std::vector<float> colour = colourHistogram(pose, bgr);
  if (colour.empty()) colour.assign(64, 0.f);
  d.insert(d.end(), colour.begin(), colour.end());
  for (float& x : d) x *= static_cast<float>(M_SQRT1_2);
  return d;
}

float appearanceSimilarity(const Descriptor& a, const Descriptor& b) {
  if (a.empty() || a.size() != b.size()) return 0.f;
  float dot = 0.f;
  for (size_t i = 0; i < a.size(); ++i) dot += a[i] * b[i];
  return dot;
}

void blendAppearance(Descriptor& a, const Descriptor& b, float alpha) {
  if (b.empty()) return;
  if (a.size() != b.size()) {
    a = b;
    return;
  }
  for (size_t i = 0; i < a.size(); ++i) a[i] = alpha * a[i] + (1.f - alpha) * b[i];
  normalise(a);
}

}  // namespace jointflow
