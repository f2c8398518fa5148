// Appearance descriptors for re-identification (appearance.hpp).
#include "jointflow/appearance.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace jointflow {
namespace {

void normalise(std::vector<float>& v) {
  double n = 0;
  for (float x : v) n += static_cast<double>(x) * x;
  if (n <= 0) return;
  const float inv = static_cast<float>(1.0 / std::sqrt(n));
  for (float& x : v) x *= inv;
}

// Head, arms (with the shoulders), legs (with the hips), COCO joint indices.
const std::array<std::vector<int>, 3> kParts = {{
    {kNose, kLeftEye, kRightEye, kLeftEar, kRightEar},
    {kLeftShoulder, kRightShoulder, kLeftElbow, kRightElbow, kLeftWrist, kRightWrist},
    {kLeftHip, kRightHip, kLeftKnee, kRightKnee, kLeftAnkle, kRightAnkle},
}};

// The mean feature vector of the frame, over every 4th cell each way: what all people share.
std::vector<float> frameMean(const cv::Mat& f) {
  const int channels = f.size[1], h = f.size[2], w = f.size[3];
  std::vector<float> mean(channels, 0.f);
  for (int c = 0; c < channels; ++c) {
    const float* plane = f.ptr<float>() + static_cast<size_t>(c) * h * w;
    double sum = 0;
    int n = 0;
    for (int y = 0; y < h; y += 4)
      for (int x = 0; x < w; x += 4, ++n) sum += plane[static_cast<size_t>(y) * w + x];
    mean[c] = n ? static_cast<float>(sum / n) : 0.f;
  }
  return mean;
}

// Per body part, the mean over its detected keypoints of (feature - frame mean), read with the
// association's bilinear sampler; each part normalised (a part not seen is zeros).
std::vector<float> partFeatures(const Pose& pose, const cv::Mat& f, const std::vector<float>& mean,
                                const GridTransform& grid, const JointThresholds& thresholds) {
  const int channels = f.size[1];
  std::vector<float> out;
  bool any = false;
  for (const std::vector<int>& part : kParts) {
    std::vector<float> sum(channels, 0.f);
    for (int j : part) {
      const Keypoint& k = pose.keypoints[j];
      if (!isDetected(k, thresholds[j])) continue;
      const cv::Point2f g = grid.toGrid({k.x, k.y});
      for (int c = 0; c < channels; ++c) sum[c] += sampleBilinear(f, c, g) - mean[c];
      any = true;
    }
    normalise(sum);
    out.insert(out.end(), sum.begin(), sum.end());
  }
  if (!any) return {};
  normalise(out);
  return out;
}

// 8 hue x 4 saturation bins and 8 value bins of the region between the keypoints `top` and
// `bottom` (as wide as they are, at least 0.3 of its height), normalised; zeros when not seen.
std::vector<float> regionColour(const Pose& pose, const cv::Mat& bgr,
                                std::initializer_list<int> top, std::initializer_list<int> bottom,
                                const JointThresholds& t) {
  std::vector<float> v(40, 0.f);
  float y0 = 1e9f, y1 = -1e9f, x0 = 1e9f, x1 = -1e9f;
  for (const auto& [joints, is_top] : {std::pair{top, true}, std::pair{bottom, false}})
    for (int j : joints) {
      const Keypoint& k = pose.keypoints[j];
      if (!isDetected(k, t[j])) continue;
      (is_top ? y0 : y1) = is_top ? std::min(y0, k.y) : std::max(y1, k.y);
      x0 = std::min(x0, k.x);
      x1 = std::max(x1, k.x);
    }
  if (!(y1 > y0) || !(x1 >= x0)) return v;
  const float w = std::max(x1 - x0, 0.3f * (y1 - y0)), cx = 0.5f * (x0 + x1);
  const cv::Rect r = cv::Rect(cv::Point(static_cast<int>(cx - w / 2), static_cast<int>(y0)),
                              cv::Point(static_cast<int>(cx + w / 2), static_cast<int>(y1))) &
                     cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (r.area() < 4) return v;
  cv::Mat hsv;
  cv::cvtColor(bgr(r), hsv, cv::COLOR_BGR2HSV);
  const int hs_channels[] = {0, 1}, hs_bins[] = {8, 4}, v_channel[] = {2}, v_bins[] = {8};
  const float hue[] = {0, 180}, sat[] = {0, 256}, val[] = {0, 256};
  const float* hs_ranges[] = {hue, sat};
  const float* v_ranges[] = {val};
  cv::Mat hs, value;
  cv::calcHist(&hsv, 1, hs_channels, cv::Mat(), hs, 2, hs_bins, hs_ranges);
  cv::calcHist(&hsv, 1, v_channel, cv::Mat(), value, 1, v_bins, v_ranges);
  std::copy(hs.begin<float>(), hs.end<float>(), v.begin());
  std::copy(value.begin<float>(), value.end<float>(), v.begin() + 32);
  normalise(v);
  return v;
}

}  // namespace

std::vector<Descriptor> describeAppearance(const Poses& poses, const std::vector<int>& which,
                                           const cv::Mat& features,
                                           const GridTransform& grid_to_frame, const cv::Mat& bgr,
                                           const JointThresholds& thresholds,
                                           AppearanceModel model) {
  std::vector<Descriptor> out(poses.size());
  if (model == AppearanceModel::kOff || features.empty() || features.dims != 4 ||
      features.type() != CV_32F)
    return out;
  const cv::Mat f = features.isContinuous() ? features : features.clone();
  const std::vector<float> mean = frameMean(f);
  const bool colour =
      model == AppearanceModel::kFeaturesColour && !bgr.empty() && bgr.type() == CV_8UC3;
  for (int i : which) {
    Descriptor d = partFeatures(poses[i], f, mean, grid_to_frame, thresholds);
    if (d.empty() || !colour) {
      out[i] = std::move(d);
      continue;
    }
    std::vector<float> c = regionColour(poses[i], bgr, {kLeftShoulder, kRightShoulder},
                                        {kLeftHip, kRightHip}, thresholds);
    const std::vector<float> legs =
        regionColour(poses[i], bgr, {kLeftHip, kRightHip}, {kLeftAnkle, kRightAnkle}, thresholds);
    c.insert(c.end(), legs.begin(), legs.end());
    normalise(c);
    // Both halves unit length, so the similarity is the mean of the two cosines.
    d.insert(d.end(), c.begin(), c.end());
    for (float& x : d) x *= static_cast<float>(M_SQRT1_2);
    out[i] = std::move(d);
  }
  return out;
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
