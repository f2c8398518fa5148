#include "jointflow/movenet_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/imgproc.hpp>

#include "tensor.hpp"

namespace jointflow {
namespace {

struct Centre {
  int row, col;
  float score;
};

/// Step 1: cells equal to their 5x5 maximum (TF MaxPool, SAME padding), highest first. The 5x5
/// maximum is cv::dilate's: its default border leaves cells outside the grid out, as SAME
/// padding does.
std::vector<Centre> centrePeaks(const cv::Mat& centre, int k) {
  const int h = centre.rows, w = centre.cols;
  cv::Mat window_max;
  cv::dilate(centre, window_max, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
  std::vector<Centre> peaks;
  for (int r = 0; r < h; ++r) {
    const float* v = centre.ptr<float>(r);
    const float* m = window_max.ptr<float>(r);
    for (int c = 0; c < w; ++c)
      if (std::abs(v[c] - m[c]) < 1.0132789611816406e-06f && v[c] > 0.f)
        peaks.push_back({r, c, v[c]});
  }
  // TopK keeps the first (row-major) index among equal scores: a stable sort does the same.
  std::stable_sort(peaks.begin(), peaks.end(),
                   [](const Centre& a, const Centre& b) { return a.score > b.score; });
  if (static_cast<int>(peaks.size()) > k) peaks.resize(k);
  return peaks;
}

struct Person {
  float ymin, xmin, ymax, xmax;                   // box, cells, clipped to the grid
  std::array<cv::Point2f, kNumJoints> regressed;  // (x, y) cells
};

}  // namespace

Poses decodeMoveNet(const MoveNetHeads& heads, const MoveNetDecodeOptions& options) {
  detail::checkTensor(heads.center, "MoveNet centre", 1, 1, {});
  const cv::Size grid(detail::cols(heads.center), detail::rows(heads.center));
  detail::checkTensor(heads.heatmaps, "MoveNet heatmaps", kNumJoints, 0, grid);
  detail::checkTensor(heads.regression, "MoveNet regression", 2 * kNumJoints, 0, grid);
  detail::checkTensor(heads.offsets, "MoveNet offsets", 2 * kNumJoints, 0, grid);
  detail::checkTensor(heads.box_scale, "MoveNet box_scale", 2, 0, grid);
  detail::checkTensor(heads.box_offset, "MoveNet box_offset", 2, 0, grid);
  const int h = grid.height, w = grid.width;

  const auto centres = centrePeaks(detail::plane(heads.center, 0), options.max_persons);
  std::vector<Person> persons;
  for (const auto& c : centres) {
    auto at = [&](const cv::Mat& t, int ch) { return t.ptr<float>(0, ch)[c.row * w + c.col]; };
    const float bh = std::max(at(heads.box_scale, 0), 0.f);
    const float bw = std::max(at(heads.box_scale, 1), 0.f);
    const float by = c.row + at(heads.box_offset, 0);
    const float bx = c.col + at(heads.box_offset, 1);
    Person p;
    p.ymin = std::clamp(by - 0.5f * bh, 0.f, static_cast<float>(h));
    p.ymax = std::clamp(by + 0.5f * bh, 0.f, static_cast<float>(h));
    p.xmin = std::clamp(bx - 0.5f * bw, 0.f, static_cast<float>(w));
    p.xmax = std::clamp(bx + 0.5f * bw, 0.f, static_cast<float>(w));
    for (int j = 0; j < kNumJoints; ++j) {
      p.regressed[j] = {c.col + at(heads.regression, 2 * j + 1),
                        c.row + at(heads.regression, 2 * j)};
    }
    persons.push_back(p);
  }

  // Step 3. The Gaussian's denominator uses the grid's smaller side, as the original graph does.
  const float denom = 0.300048828125f * static_cast<float>(std::min(h, w));
  auto weighted = [&](const Person& p, int j, int r, int col) -> float {
    if (r < p.ymin || r >= p.ymax || col < p.xmin || col >= p.xmax) return 0.f;
    const float dy = r - p.regressed[j].y, dx = col - p.regressed[j].x;
    return heads.heatmaps.ptr<float>(0, j)[r * w + col] * std::exp(-(dx * dx + dy * dy) / denom);
  };

  Poses poses;
  for (size_t i = 0; i < persons.size(); ++i) {
    if (centres[i].score < options.min_centre_score) continue;
    const Person& p = persons[i];
    Pose pose;
    float sum = 0.f;
    int counted = 0;
    for (int j = 0; j < kNumJoints; ++j) {
      // argmax over the grid in row-major order, the first maximum winning (tf.argmax). Cells
      // outside the box weigh 0, so scanning the box suffices; when every weight is 0 the
      // argmax is cell (0, 0).
      int best_r = 0, best_c = 0;
      float best = 0.f;
      const float* heat = heads.heatmaps.ptr<float>(0, j);
      for (int r = static_cast<int>(std::ceil(p.ymin)); r < p.ymax; ++r) {
        for (int col = static_cast<int>(std::ceil(p.xmin)); col < p.xmax; ++col) {
          // The Gaussian weight is at most 1, so a cell whose belief is no more than the best
          // so far cannot win: its exp() is skipped (the same result, at a fraction of the cost).
          if (heat[r * w + col] <= best) continue;
          const float v = weighted(p, j, r, col);
          if (v > best) best = v, best_r = r, best_c = col;
        }
      }
      float score = 0.f;
      for (const auto& q : persons) score = std::max(score, weighted(q, j, best_r, best_c));
      const float oy = heads.offsets.ptr<float>(0, 2 * j)[best_r * w + best_c];
      const float ox = heads.offsets.ptr<float>(0, 2 * j + 1)[best_r * w + best_c];
      pose.keypoints[j] = {best_c + ox, best_r + oy, score};
      if (score > options.joint_score_threshold) sum += score, ++counted;
    }
    pose.score = centres[i].score * (counted > 0 ? sum / counted : 0.f);
    pose.box = {p.xmin, p.ymin, p.xmax - p.xmin, p.ymax - p.ymin};
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace jointflow
