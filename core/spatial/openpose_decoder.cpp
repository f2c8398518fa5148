#include "jointflow/openpose_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "jointflow/error.hpp"
#include "tensor.hpp"

namespace jointflow {
namespace {

struct Peak {
  cv::Point2f pos;  // cells
  float score;
};

/// Offset of a parabola's vertex through (-1, a), (0, b), (1, c): exact for log of a Gaussian.
float parabolaVertex(float a, float b, float c) {
  const float den = a - 2.f * b + c;
  if (!(den < 0.f)) return 0.f;
  return std::clamp(0.5f * (a - c) / den, -0.5f, 0.5f);
}

/// Step 1: 3x3 non-maximum suppression with threshold tau_NMS, sub-cell refinement.
std::vector<Peak> findPeaks(const cv::Mat& map, float tau) {
  std::vector<Peak> peaks;
  const int h = map.rows, w = map.cols;
  auto v = [&](int r, int c) {
    return map.at<float>(std::clamp(r, 0, h - 1), std::clamp(c, 0, w - 1));
  };
  auto logv = [&](int r, int c) { return std::log(std::max(v(r, c), 1e-30f)); };
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const float s = v(r, c);
      if (!(s > tau)) continue;
      bool is_max = true;
      for (int dr = -1; dr <= 1 && is_max; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if ((dr || dc) && rr >= 0 && rr < h && cc >= 0 && cc < w && map.at<float>(rr, cc) > s) {
            is_max = false;
            break;
          }
        }
      }
      if (!is_max) continue;
      // A plateau would give several peaks: keep only the first (row-major) cell of one.
      bool earlier_equal = false;
      for (int dr = -1; dr <= 0 && !earlier_equal; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if (dr == 0 && dc >= 0) break;
          const int rr = r + dr, cc = c + dc;
          if (rr >= 0 && cc >= 0 && cc < w && map.at<float>(rr, cc) == s) {
            earlier_equal = true;
            break;
          }
        }
      }
      if (earlier_equal) continue;
      const float dx =
          (c > 0 && c < w - 1) ? parabolaVertex(logv(r, c - 1), logv(r, c), logv(r, c + 1)) : 0.f;
      const float dy =
          (r > 0 && r < h - 1) ? parabolaVertex(logv(r - 1, c), logv(r, c), logv(r + 1, c)) : 0.f;
      peaks.push_back({{c + dx, r + dy}, s});
    }
  }
  return peaks;
}

struct Connection {
  int a, b;  // peak indices into the limb's two joints' peak lists
  float score;
};

/// Step 2: the PAF line integral between two candidates (Cao et al. Eq. 10, sampled), with the
/// distance prior of their implementation; returns false where the limb is implausible.
bool limbScore(const cv::Mat& paf_x, const cv::Mat& paf_y, cv::Point2f pa, cv::Point2f pb,
               const OpenPoseDecodeOptions& o, float* score) {
  const cv::Point2f d = pb - pa;
  const float norm = std::sqrt(d.dot(d));
  if (norm < 1e-6f) return false;
  const cv::Point2f u = d / norm;
  const int h = paf_x.rows, w = paf_x.cols;
  float sum = 0.f;
  int above = 0;
  const int n = std::max(o.line_samples, 2);
  for (int i = 0; i < n; ++i) {
    const cv::Point2f p = pa + d * (static_cast<float>(i) / (n - 1));
    const int c = std::clamp(static_cast<int>(std::lround(p.x)), 0, w - 1);
    const int r = std::clamp(static_cast<int>(std::lround(p.y)), 0, h - 1);
    const float s = paf_x.at<float>(r, c) * u.x + paf_y.at<float>(r, c) * u.y;
    sum += s;
    if (s > o.paf_threshold) ++above;
  }
  const float prior = std::min(0.f, 0.5f * h / norm - 1.f);
  *score = sum / n + prior;
  return *score > 0.f && above > 0.8f * n;
}

}  // namespace

Poses decodeOpenPose(const cv::Mat& beliefs, const cv::Mat& pafs, const OpenPoseDecodeOptions& o) {
  detail::checkTensor(beliefs, "OpenPose beliefs", -1, kNumJoints, {});
  const cv::Size grid(detail::cols(beliefs), detail::rows(beliefs));
  detail::checkTensor(pafs, "OpenPose PAFs (2 channels per limb of the limb list)",
                      2 * static_cast<int>(o.limbs.size()), 0, grid);
  for (const auto& [a, b] : o.limbs) {
    if (a < 0 || a >= kNumJoints || b < 0 || b >= kNumJoints || a == b) {
      std::ostringstream msg;
      msg << "OpenPose limb (" << a << ", " << b << ") is not a pair of two COCO joints 0..16";
      throw Error(msg.str());
    }
  }

  std::array<std::vector<Peak>, kNumJoints> peaks;
  for (int j = 0; j < kNumJoints; ++j)
    peaks[j] = findPeaks(detail::plane(beliefs, j), o.nms_threshold);

  // Persons as peak indices per joint (-1 = absent), with their accumulated score.
  struct Person {
    std::array<int, kNumJoints> peak;
    float score = 0.f;
    int count = 0;
  };
  std::vector<Person> persons;
  auto newPerson = [] {
    Person p;
    p.peak.fill(-1);
    return p;
  };

  for (size_t l = 0; l < o.limbs.size(); ++l) {
    const auto [ja, jb] = o.limbs[l];
    const cv::Mat px = detail::plane(pafs, 2 * static_cast<int>(l));
    const cv::Mat py = detail::plane(pafs, 2 * static_cast<int>(l) + 1);
    std::vector<Connection> candidates;
    for (int a = 0; a < static_cast<int>(peaks[ja].size()); ++a) {
      for (int b = 0; b < static_cast<int>(peaks[jb].size()); ++b) {
        float s;
        if (limbScore(px, py, peaks[ja][a].pos, peaks[jb][b].pos, o, &s))
          candidates.push_back({a, b, s});
      }
    }
    // Step 3: greedy bipartite matching, best connections first, each joint used once.
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Connection& x, const Connection& y) { return x.score > y.score; });
    std::vector<bool> used_a(peaks[ja].size()), used_b(peaks[jb].size());
    std::vector<Connection> chosen;
    for (const auto& c : candidates) {
      if (used_a[c.a] || used_b[c.b]) continue;
      used_a[c.a] = used_b[c.b] = true;
      chosen.push_back(c);
    }
    // Step 4: person assembly.
    for (const auto& c : chosen) {
      std::vector<size_t> owners;
      for (size_t i = 0; i < persons.size(); ++i) {
        if (persons[i].peak[ja] == c.a || persons[i].peak[jb] == c.b) owners.push_back(i);
      }
      if (owners.size() == 1) {
        Person& p = persons[owners[0]];
        if (p.peak[jb] == -1) {
          p.peak[jb] = c.b, p.score += peaks[jb][c.b].score, ++p.count;
        } else if (p.peak[ja] == -1) {
          p.peak[ja] = c.a, p.score += peaks[ja][c.a].score, ++p.count;
        }
        p.score += c.score;
      } else if (owners.size() == 2) {
        Person& p = persons[owners[0]];
        Person& q = persons[owners[1]];
        bool disjoint = true;
        for (int j = 0; j < kNumJoints; ++j) disjoint &= p.peak[j] == -1 || q.peak[j] == -1;
        if (disjoint) {
          for (int j = 0; j < kNumJoints; ++j) {
            if (q.peak[j] != -1) p.peak[j] = q.peak[j];
          }
          p.score += q.score + c.score;
          p.count += q.count;
          persons.erase(persons.begin() + static_cast<long>(owners[1]));
        }
      } else if (owners.empty()) {
        Person p = newPerson();
        p.peak[ja] = c.a;
        p.peak[jb] = c.b;
        p.score = peaks[ja][c.a].score + peaks[jb][c.b].score + c.score;
        p.count = 2;
        persons.push_back(p);
      }
    }
  }

  Poses poses;
  for (const auto& p : persons) {
    if (p.count < o.min_parts) continue;
    Pose pose;
    float sum = 0.f;
    for (int j = 0; j < kNumJoints; ++j) {
      if (p.peak[j] < 0) continue;
      const Peak& k = peaks[j][p.peak[j]];
      pose.keypoints[j] = {k.pos.x, k.pos.y, k.score};
      sum += k.score;
    }
    pose.score = sum / p.count;
    pose.box = pose.keypointBox(0.f);
    poses.push_back(pose);
  }
  std::stable_sort(poses.begin(), poses.end(),
                   [](const Pose& a, const Pose& b) { return a.score > b.score; });
  if (static_cast<int>(poses.size()) > o.max_persons) poses.resize(o.max_persons);
  return poses;
}

}  // namespace jointflow
