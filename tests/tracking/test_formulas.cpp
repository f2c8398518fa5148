// The paper's formulas against hand-computed values: TFF rendering (Eq. 2-4), E_aggr (Eq. 5),
// the tau_delta case (Eq. 6), Psi (Eq. 7), the baselines (Eq. 8) and the flow energy (Eq. 9).
#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/similarity.hpp"
#include "jointflow/temporal_flow.hpp"

using namespace jointflow;

namespace {

float at(const cv::Mat& field, int channel, int y, int x) {
  const int idx[] = {0, channel, y, x};
  return field.at<float>(idx);
}

// A {1, 34, h, w} field that holds the same vector for every joint at every cell.
cv::Mat uniformField(int h, int w, float vx, float vy) {
  const int sizes[] = {1, 2 * kNumJoints, h, w};
  cv::Mat f(4, sizes, CV_32F);
  for (int c = 0; c < 2 * kNumJoints; ++c) {
    cv::Mat plane(h, w, CV_32F, f.ptr<float>() + static_cast<size_t>(c) * h * w);
    plane.setTo(c % 2 ? vy : vx);
  }
  return f;
}

Pose poseWith(std::initializer_list<std::pair<int, Keypoint>> joints) {
  Pose p;
  for (const auto& [j, k] : joints) p.keypoints[j] = k;
  p.score = 1.f;
  return p;
}

int nonZero(const cv::Mat& f) {
  return static_cast<int>(
      std::count_if(f.ptr<float>(), f.ptr<float>() + f.total(), [](float v) { return v != 0.f; }));
}

JointThresholds thresholds(float t) {
  JointThresholds a;
  a.fill(t);
  return a;
}

}  // namespace

TEST_CASE("TFF rendering follows Eq. 2-4 cell by cell", "[tracking][tff]") {
  SECTION("a horizontal motion covers the segment widened by sigma, inclusive") {
    const cv::Mat f = renderTemporalFlowField({{3, {2, 2}, {6, 2}}}, kNumJoints, {10, 6}, 1.f);
    REQUIRE(f.dims == 4);
    REQUIRE(f.size[1] == 34);
    REQUIRE(f.size[2] == 6);
    REQUIRE(f.size[3] == 10);
    int inside = 0;
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 10; ++x) {
        const bool omega = x >= 2 && x <= 6 && y >= 1 && y <= 3;
        CHECK(at(f, 6, y, x) == (omega ? 1.f : 0.f));
        CHECK(at(f, 7, y, x) == 0.f);
        inside += omega;
      }
    CHECK(inside == 15);
    CHECK(nonZero(f) == 15);
  }
  SECTION("a diagonal motion: v = (0.6, 0.8), membership by projection") {
    const cv::Mat f = renderTemporalFlowField({{0, {0, 0}, {3, 4}}}, kNumJoints, {8, 8}, 1.f);
    // (1,1): along 1.4 in [0,5], across 0.2 -> inside.
    CHECK(at(f, 0, 1, 1) == Approx(0.6f));
    CHECK(at(f, 1, 1, 1) == Approx(0.8f));
    // (3,0): across |-0.8 * 3| = 2.4 > 1 -> outside. (4,5): along 6.4 > 5 -> outside.
    CHECK(at(f, 0, 0, 3) == 0.f);
    CHECK(at(f, 0, 5, 4) == 0.f);
    // (3,4), the end point: along exactly 5 = lambda -> inside.
    CHECK(at(f, 1, 4, 3) == Approx(0.8f));
  }
  SECTION("overlapping persons are averaged over the non-zero vectors (Eq. 4)") {
    const cv::Mat f = renderTemporalFlowField({{5, {0, 3}, {6, 3}}, {5, {3, 0}, {3, 6}}},
                                              kNumJoints, {7, 7}, 0.f);
    CHECK(at(f, 10, 3, 3) == Approx(0.5f));  // (1,0) and (0,1) meet at (3,3)
    CHECK(at(f, 11, 3, 3) == Approx(0.5f));
    CHECK(at(f, 10, 3, 1) == 1.f);  // only the horizontal one
    CHECK(at(f, 11, 1, 3) == 1.f);  // only the vertical one
  }
  SECTION("no motion renders nothing; other joints stay empty") {
    const cv::Mat f = renderTemporalFlowField({{2, {3, 3}, {3, 3}}}, kNumJoints, {7, 7}, 1.f);
    CHECK(nonZero(f) == 0);
  }
  SECTION("bad input is refused with a message") {
    CHECK_THROWS_AS(renderTemporalFlowField({{17, {0, 0}, {1, 1}}}, kNumJoints, {4, 4}, 1.f),
                    Error);
    CHECK_THROWS_WITH(renderTemporalFlowField({}, kNumJoints, {4, 4}, -1.f),
                      Catch::Contains("sigma"));
    CHECK_THROWS_AS(renderTemporalFlowField({}, kNumJoints, {0, 4}, 1.f), Error);
    CHECK_THROWS_AS(renderTemporalFlowField({}, 0, {4, 4}, 1.f), Error);
  }
}

TEST_CASE("jointMotions maps frame pixels to grid cells", "[tracking][tff]") {
  Pose a = poseWith({{kNose, {10, 20, 1}}, {kLeftEye, {5, 5, 0.05f}}});
  Pose b = poseWith({{kNose, {30, 28, 1}}, {kLeftEye, {9, 9, 1}}});
  const auto m = jointMotions(a, b, GridTransform{4, 4, 2, 4}, 0.1f);
  REQUIRE(m.size() == 1);
  CHECK(m[0].joint == kNose);
  CHECK(m[0].from.x == Approx(2.f));
  CHECK(m[0].from.y == Approx(4.f));
  CHECK(m[0].to.x == Approx(7.f));
  CHECK(m[0].to.y == Approx(6.f));
}

TEST_CASE("bilinear sampling and the flow field aggregate (Eq. 5)", "[tracking][similarity]") {
  const int h = 6, w = 11;
  const int sizes[] = {1, 2 * kNumJoints, h, w};
  cv::Mat ramp(4, sizes, CV_32F, cv::Scalar(0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int ix[] = {0, 0, y, x};
      ramp.at<float>(ix) = x / 10.f + y;  // linear: bilinear sampling is exact
    }
  CHECK(sampleBilinear(ramp, 0, {2.5f, 1.25f}) == Approx(0.25f + 1.25f));
  CHECK(sampleBilinear(ramp, 0, {-3.f, 0.f}) == Approx(0.f));  // clamped to the grid
  CHECK(sampleBilinear(ramp, 0, {20.f, 5.f}) == Approx(1.f + 5.f));

  // T_x = x/10 along y = 0 from x = 0 to 10: the mean of 0, 0.1, ..., 1 = 0.5.
  CHECK(flowFieldAggregate(ramp, 0, {0, 0}, {10, 0}, 11) == Approx(0.5f));
  // Against the motion: -0.5; perpendicular: the y channel is 0 -> 0.
  CHECK(flowFieldAggregate(ramp, 0, {10, 0}, {0, 0}, 11) == Approx(-0.5f));
  CHECK(flowFieldAggregate(ramp, 0, {3, 0}, {3, 5}, 11) == Approx(0.f));
  CHECK(flowFieldAggregate(ramp, 0, {3, 3}, {3, 3}, 11) == 0.f);

  const cv::Mat right = uniformField(8, 8, 1.f, 0.f);
  CHECK(flowFieldAggregate(right, 4, {1, 1}, {5, 5}, 10) == Approx(std::sqrt(0.5f)));
}

TEST_CASE("joint potential: tau_delta in frame pixels, E_aggr on the grid (Eq. 6)",
          "[tracking][similarity]") {
  const cv::Mat right = uniformField(20, 20, 1.f, 0.f);
  const GridTransform stride4{4, 4, 0, 0};
  // 1.9 px < tau_delta = 2 px: E_j = 1 whatever the field says.
  CHECK(jointPotential(right, stride4, 0, {40, 40}, {40, 41.9f}, 2.f, 10) == 1.f);
  // 2 px is not below tau_delta: E_aggr, here perpendicular to the field -> 0.
  CHECK(jointPotential(right, stride4, 0, {40, 40}, {40, 42}, 2.f, 10) == Approx(0.f));
  // 40 px along the field, against it.
  CHECK(jointPotential(right, stride4, 0, {10, 40}, {50, 40}, 2.f, 10) == Approx(1.f));
  CHECK(jointPotential(right, stride4, 0, {50, 40}, {10, 40}, 2.f, 10) == Approx(-1.f));
  // Anisotropic grid scaling: 40 px right and 40 px down is 10 cells right and 5 down on a grid
  // of stride (4, 8); the field (1, 0) . (10, 5)/|(10, 5)| = 2/sqrt(5).
  const GridTransform aniso{4, 8, 0, 0};
  CHECK(jointPotential(right, aniso, 0, {0, 0}, {40, 40}, 2.f, 10) == Approx(2.f / std::sqrt(5.f)));
}

TEST_CASE("person potential Psi sums over joints detected in both (Eq. 7)",
          "[tracking][similarity]") {
  const cv::Mat right = uniformField(30, 30, 1.f, 0.f);
  const GridTransform stride4{4, 4, 0, 0};
  const Pose prev = poseWith({{kNose, {40, 40, 1}},            // still: E = 1
                              {kLeftWrist, {20, 60, 1}},       // moves with the field: E = 1
                              {kRightWrist, {80, 60, 1}},      // moves against it: E = -1
                              {kLeftKnee, {50, 90, 1}},        // missing in the current pose
                              {kRightKnee, {60, 90, 0.1f}}});  // below its threshold
  const Pose cur = poseWith({{kNose, {40.5f, 40, 1}},
                             {kLeftWrist, {60, 60, 1}},
                             {kRightWrist, {40, 60, 1}},
                             {kRightKnee, {100, 90, 1}},
                             {kLeftAnkle, {10, 10, 1}}});
  // Through the similarity the tracker uses: Psi = 1 + 1 - 1 over 3 joints in both.
  SimilarityOptions o;
  o.thresholds = thresholds(0.2f);
  const SimilarityInput in{right, stride4, {}};
  Potentials p = createSimilarity(SimilarityType::kTff, o)->compute({prev}, {cur}, in);
  CHECK(p.psi.at<float>(0, 0) == Approx(1.f));
  CHECK(p.per_joint.at<float>(0, 0) == Approx(1.f / 3.f));
  // With the right knee's threshold lowered it counts: +1 (moves with the field), 4 joints.
  o.thresholds[kRightKnee] = 0.05f;
  p = createSimilarity(SimilarityType::kTff, o)->compute({prev}, {cur}, in);
  CHECK(p.psi.at<float>(0, 0) == Approx(2.f));
  CHECK(p.per_joint.at<float>(0, 0) == Approx(0.5f));
  // The same sum through personPotential with Eq. 6 as the energy.
  int common = 0;
  const float psi = personPotential(
      prev, cur, o.thresholds,
      [&](int j, const Keypoint& a, const Keypoint& b) {
        return jointPotential(right, stride4, j, {a.x, a.y}, {b.x, b.y}, 2.f, 10);
      },
      &common);
  CHECK(psi == Approx(2.f));
  CHECK(common == 4);
}

TEST_CASE("the tff potential matrix pairs every track with every pose (Eq. 7, hand computed)",
          "[tracking][similarity]") {
  // A field pointing right on the whole grid: a joint that moved right scores 1, left -1,
  // straight down 0, and one that moved less than tau_delta (2 px) scores 1.
  const cv::Mat right = uniformField(40, 40, 1.f, 0.f);
  const GridTransform stride4{4, 4, 0, 0};
  const Pose a = poseWith({{kNose, {20, 20, 1}}, {kLeftHip, {20, 60, 1}}});
  const Pose b =
      poseWith({{kNose, {100, 20, 1}}, {kLeftHip, {100, 60, 1}}, {kLeftAnkle, {1, 1, 1}}});
  const Pose a_next = poseWith({{kNose, {60, 20, 1}}, {kLeftHip, {60, 60, 1}}});  // a, 40 px right
  const Pose b_next =
      poseWith({{kNose, {100.5f, 20, 1}}, {kLeftHip, {100, 100, 1}}});  // b: still, down
  SimilarityOptions o;
  o.thresholds = thresholds(0.2f);
  const Potentials p = createSimilarity(SimilarityType::kTff, o)
                           ->compute({a, b}, {a_next, b_next}, {right, stride4, {}});
  // a -> a_next: both joints moved right: 1 + 1.
  CHECK(p.psi.at<float>(0, 0) == Approx(2.f));
  // a -> b_next: nose 80.5 px right (1), hip 80 px right and 40 down (80/sqrt(80^2+40^2)).
  CHECK(p.psi.at<float>(0, 1) == Approx(1.f + 2.f / std::sqrt(5.f)));
  // b -> a_next: both moved 40 px left: -1 - 1 (the ankle is not in a_next).
  CHECK(p.psi.at<float>(1, 0) == Approx(-2.f));
  CHECK(p.per_joint.at<float>(1, 0) == Approx(-1.f));
  // b -> b_next: the nose moved 0.5 px (< tau_delta): 1; the hip straight down: 0.
  CHECK(p.psi.at<float>(1, 1) == Approx(1.f));
  CHECK(p.per_joint.at<float>(1, 1) == Approx(0.5f));
}

TEST_CASE("baseline similarities against hand-computed values (Eq. 8, 9)",
          "[tracking][similarity]") {
  const JointThresholds t = thresholds(0.2f);
  SECTION("OKS") {
    // Boxes 30x40 and 27x36 -> s^2 = 1200 (the larger); left shoulder off by 5 px (k = 0.158),
    // right hip exact: (exp(-25 / (2 * 1200 * 0.158^2)) + 1) / 2 = (0.658845 + 1) / 2.
    const Pose a = poseWith({{kLeftShoulder, {0, 0, 1}}, {kRightHip, {30, 40, 1}}});
    const Pose b = poseWith({{kLeftShoulder, {3, 4, 1}}, {kRightHip, {30, 40, 1}}});
    CHECK(oks(a, b, t) == Approx(0.8294223).epsilon(1e-5));
    CHECK(oks(a, a, t) == Approx(1.f));
    CHECK(oks(a, Pose{}, t) == 0.f);
    // Over at least 5 joints (min_common_joints): the 2 in common count 2 / 5 of their mean.
    CHECK(oks(a, b, t, 0.f, 5) == Approx(0.8294223 * 2 / 5).epsilon(1e-5));
    CHECK(oks(a, b, t, 0.f, 2) == Approx(0.8294223).epsilon(1e-5));
  }
  SECTION("PCKh with a head size estimated from the shoulders, else the ears") {
    // Shoulder widths 50 -> head sizes 0.63 * 50 = 31.5 -> radius 15.75 px; of 4 common joints
    // the left shoulder (5 px), right shoulder (5 px) and left hip (10 px) lie within, the right
    // hip (16.03 px) does not.
    const Pose a = poseWith({{kLeftShoulder, {0, 0, 1}},
                             {kRightShoulder, {50, 0, 1}},
                             {kLeftHip, {0, 100, 1}},
                             {kRightHip, {50, 100, 1}}});
    const Pose b = poseWith({{kLeftShoulder, {5, 0, 1}},
                             {kRightShoulder, {55, 0, 1}},
                             {kLeftHip, {0, 110, 1}},
                             {kRightHip, {51, 116, 1}}});
    CHECK(headSize(a, t) == Approx(31.5f));
    CHECK(pckh(a, b, t) == Approx(0.75f));
    CHECK(pckh(a, b, t, 6) == Approx(0.5f));  // 3 of at least 6
    // Without shoulders: 1.6 x the ear distance.
    const Pose e = poseWith({{kLeftEar, {0, 0, 1}}, {kRightEar, {20, 0, 1}}});
    CHECK(headSize(e, t) == Approx(32.f));
    // Neither: the keypoint box's longer side / 7.5.
    const Pose n = poseWith({{kNose, {0, 0, 1}}, {kLeftAnkle, {10, 150, 1}}});
    CHECK(headSize(n, t) == Approx(20.f));
  }
  SECTION("IoU of the pose boxes") {
    // Boxes [0,10]x[0,10] and [5,15]x[0,10]: 50 / 150.
    const Pose a = poseWith({{kNose, {0, 0, 1}}, {kLeftAnkle, {10, 10, 1}}});
    const Pose b = poseWith({{kNose, {5, 0, 1}},
                             {kLeftAnkle, {15, 10, 1}},
                             {kRightAnkle, {100, 100, 0.1f}}});  // below threshold: not in box
    CHECK(poseBoxIou(a, b, t) == Approx(1.f / 3.f));
  }
  SECTION("optical-flow energy") {
    CHECK(flowEnergy({10, 10}, {25, 10}, {15, 0}, 30.f) == Approx(1.f));
    CHECK(flowEnergy({10, 10}, {55, 10}, {15, 0}, 30.f) == Approx(std::exp(-1.f)));
  }
}

TEST_CASE("similarities are chosen by name", "[tracking][similarity]") {
  for (const auto& e : EnumInfo<SimilarityType>::kEntries) {
    CHECK(createSimilarity(parseEnum<SimilarityType>(e.nick), {})->type() == e.value);
    CHECK(std::string(toString(e.value)) == e.nick);
  }
  CHECK_THROWS_WITH(parseEnum<SimilarityType>("hog"),
                    Catch::Contains("unknown similarity 'hog'") &&
                        Catch::Contains("tff, oks, iou, pckh, flow or auto"));
  // "tff" without its map says what it needs.
  const Poses one = {poseWith({{kNose, {1, 1, 1}}})};
  CHECK_THROWS_WITH(createSimilarity(SimilarityType::kTff, {})->compute(one, one, {}),
                    Catch::Contains("TFF map"));
  CHECK_THROWS_WITH(createSimilarity(SimilarityType::kFlow, {})->compute(one, one, {}),
                    Catch::Contains("optical flow"));
}
