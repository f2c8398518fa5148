// The three decoders on synthetic tensors whose answer is known exactly.
#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/movenet_decoder.hpp"
#include "jointflow/openpose_decoder.hpp"
#include "jointflow/posenet_decoder.hpp"
#include "render_maps.hpp"

using namespace jointflow;

namespace {

cv::Mat zeros(int c, int h, int w) {
  return cv::Mat(std::vector<int>{1, c, h, w}, CV_32F, cv::Scalar(0));
}
float& at(cv::Mat& t, int c, int r, int col) {
  return t.ptr<float>(0, c)[r * t.size[3] + col];
}

// One MoveNet person: centre cell, box, and per joint the cell its heatmap peaks at.
struct MnPerson {
  int row, col;
  float centre;
  float box_h, box_w;
  std::array<cv::Point, kNumJoints> cells;  // (col, row)
  std::array<float, kNumJoints> heat;
};

void writeMoveNet(MoveNetHeads& m, const MnPerson& p) {
  at(m.center, 0, p.row, p.col) = p.centre;
  at(m.box_scale, 0, p.row, p.col) = p.box_h;
  at(m.box_scale, 1, p.row, p.col) = p.box_w;
  for (int j = 0; j < kNumJoints; ++j) {
    // Regression points exactly at the joint cell, so the Gaussian weight there is 1.
    at(m.regression, 2 * j, p.row, p.col) = static_cast<float>(p.cells[j].y - p.row);
    at(m.regression, 2 * j + 1, p.row, p.col) = static_cast<float>(p.cells[j].x - p.col);
    at(m.heatmaps, j, p.cells[j].y, p.cells[j].x) = p.heat[j];
    at(m.offsets, 2 * j, p.cells[j].y, p.cells[j].x) = 0.25f;
    at(m.offsets, 2 * j + 1, p.cells[j].y, p.cells[j].x) = -0.375f;
  }
}

}  // namespace

TEST_CASE("MoveNet decoding finds centres, joints inside each box, and the graph's scores") {
  const int h = 16, w = 24;
  MoveNetHeads m{zeros(1, h, w),  zeros(17, h, w), zeros(34, h, w),
                 zeros(34, h, w), zeros(2, h, w),  zeros(2, h, w)};
  MnPerson a{5, 4, 0.9f, 8.f, 6.f, {}, {}};
  MnPerson b{9, 16, 0.8f, 10.f, 6.f, {}, {}};
  for (int j = 0; j < kNumJoints; ++j) {
    a.cells[j] = {2 + j % 5, 2 + j / 5};   // rows 2..5, cols 2..6: inside a's box [1,9) x [1,7)
    b.cells[j] = {14 + j % 5, 5 + j / 5};  // inside b's box [4,14) x [13,19)
    a.heat[j] = j < 2 ? 0.1f : (j < 9 ? 0.7f : 0.5f);  // joints 0, 1 below 0.127
    b.heat[j] = 0.6f;
  }
  writeMoveNet(m, a);
  writeMoveNet(m, b);
  // A stronger distractor for a's nose outside a's box (inside b's): a must not take it.
  at(m.heatmaps, kNose, 8, 15) = 0.95f;
  // A weaker centre next to a's: not a 5x5 maximum, so no third person.
  at(m.center, 0, 6, 5) = 0.85f;

  MoveNetDecodeOptions o;
  o.max_persons = 5;
  const Poses poses = decodeMoveNet(m, o);
  REQUIRE(poses.size() == 2);
  const Pose& pa = poses[0];
  CHECK(pa.score == Approx(0.9f * (7 * 0.7f + 8 * 0.5f) / 15).epsilon(1e-6));
  for (int j = 0; j < kNumJoints; ++j) {
    INFO("joint " << j);
    CHECK(pa.keypoints[j].x == Approx(a.cells[j].x - 0.375f).margin(1e-6));
    CHECK(pa.keypoints[j].y == Approx(a.cells[j].y + 0.25f).margin(1e-6));
    CHECK(pa.keypoints[j].score == Approx(a.heat[j]).margin(1e-6));
  }
  CHECK(pa.box.x == Approx(1.f));
  CHECK(pa.box.y == Approx(1.f));
  CHECK(pa.box.w == Approx(6.f));
  CHECK(pa.box.h == Approx(8.f));
  // b's nose: the distractor at (15, 8) is nearer b's nose cell (14, 5)? No: b's regressed nose
  // is (14, 5); the distractor lies 3.16 cells away, weight exp(-10/4.8) = 0.125, 0.95 * 0.125
  // = 0.118 < 0.6, so b keeps its own nose.
  const Pose& pb = poses[1];
  CHECK(pb.keypoints[kNose].x == Approx(14 - 0.375f));
  CHECK(pb.keypoints[kNose].y == Approx(5 + 0.25f));
  CHECK(pb.score == Approx(0.8f * 0.6f).epsilon(1e-6));

  o.max_persons = 1;
  CHECK(decodeMoveNet(m, o).size() == 1);

  // Below b's centre score (0.8): a alone, exactly as among all (b still counts in a's joints).
  o.max_persons = 5;
  o.min_centre_score = 0.85f;
  const Poses only_a = decodeMoveNet(m, o);
  REQUIRE(only_a.size() == 1);
  CHECK(only_a[0].score == pa.score);
  CHECK(only_a[0].box.w == pa.box.w);
  for (int j = 0; j < kNumJoints; ++j) {
    CHECK(only_a[0].keypoints[j].x == pa.keypoints[j].x);
    CHECK(only_a[0].keypoints[j].y == pa.keypoints[j].y);
    CHECK(only_a[0].keypoints[j].score == pa.keypoints[j].score);
  }
}

TEST_CASE("MoveNet decoding rejects tensors of mismatched shapes") {
  MoveNetHeads m{zeros(1, 8, 8),  zeros(17, 8, 8), zeros(34, 8, 8),
                 zeros(34, 8, 9), zeros(2, 8, 8),  zeros(2, 8, 8)};
  REQUIRE_THROWS_WITH(decodeMoveNet(m, {}),
                      Catch::Contains("MoveNet offsets") && Catch::Contains("expected a 8x8 grid"));
  m.offsets = zeros(34, 8, 8);
  m.heatmaps = zeros(16, 8, 8);
  REQUIRE_THROWS_WITH(decodeMoveNet(m, {}),
                      Catch::Contains("MoveNet heatmaps: expected 17 channels"));
}

namespace {

// Writes one PoseNet person: joint j at cell cells[j] with offset (dy, dx) and score; the
// displacements of every tree edge point exactly between the joints' positions.
void writePoseNet(PoseNetHeads& p, const std::array<cv::Point, kNumJoints>& cells,
                  const std::array<cv::Point2f, kNumJoints>& offsets,
                  const std::array<float, kNumJoints>& scores,
                  std::array<cv::Point2f, kNumJoints>* positions) {
  for (int j = 0; j < kNumJoints; ++j) {
    at(p.scores, j, cells[j].y, cells[j].x) = scores[j];
    at(p.offsets, j, cells[j].y, cells[j].x) = offsets[j].y;
    at(p.offsets, j + kNumJoints, cells[j].y, cells[j].x) = offsets[j].x;
    (*positions)[j] = {cells[j].x * 16.f + offsets[j].x, cells[j].y * 16.f + offsets[j].y};
  }
  for (int e = 0; e < 16; ++e) {
    const auto [parent, child] = kPoseNetEdges[e];
    const cv::Point2f d = (*positions)[child] - (*positions)[parent];
    at(p.displacement_fwd, e, cells[parent].y, cells[parent].x) = d.y;
    at(p.displacement_fwd, 16 + e, cells[parent].y, cells[parent].x) = d.x;
    at(p.displacement_bwd, e, cells[child].y, cells[child].x) = -d.y;
    at(p.displacement_bwd, 16 + e, cells[child].y, cells[child].x) = -d.x;
  }
}

}  // namespace

TEST_CASE("PoseNet decoding follows the displacement tree from the best part, with pose NMS") {
  const int h = 13, w = 17;
  PoseNetHeads p{zeros(17, h, w), zeros(34, h, w), zeros(32, h, w), zeros(32, h, w)};
  // Person A around column 4, person B around column 12; B's best part is its left wrist, so
  // its decoding must go up the tree (backward displacements) before coming down.
  std::array<cv::Point, kNumJoints> ca, cb;
  std::array<cv::Point2f, kNumJoints> oa, ob;
  std::array<float, kNumJoints> sa, sb;
  const int layout[kNumJoints][2] = {{0, 1}, {-1, 1}, {1, 1}, {-2, 1},  {2, 1}, {-1, 3},
                                     {1, 3}, {-2, 5}, {2, 5}, {-2, 7},  {2, 7}, {-1, 7},
                                     {1, 7}, {-1, 9}, {1, 9}, {-1, 11}, {1, 11}};
  for (int j = 0; j < kNumJoints; ++j) {
    ca[j] = {4 + layout[j][0], layout[j][1]};
    cb[j] = {12 + layout[j][0], layout[j][1]};
    oa[j] = {0.5f * j - 4.f, 3.f - 0.25f * j};
    ob[j] = {2.f - 0.125f * j, 0.5f * (j % 5) - 1.f};
    sa[j] = 0.3f + 0.01f * j;
    sb[j] = 0.35f;
  }
  sa[kNose] = 0.9f;
  sa[kLeftShoulder] = 0.8f;  // a root candidate too, suppressed by A's decoded left shoulder
  sb[kLeftWrist] = 0.95f;
  std::array<cv::Point2f, kNumJoints> pa, pb;
  writePoseNet(p, ca, oa, sa, &pa);
  writePoseNet(p, cb, ob, sb, &pb);

  PoseNetDecodeOptions o;
  const Poses poses = decodePoseNet(p, o);
  REQUIRE(poses.size() == 2);
  const Pose& first = poses[0];  // B: root score 0.95
  const Pose& second = poses[1];
  float sum_a = 0.f, sum_b = 0.f;
  for (int j = 0; j < kNumJoints; ++j) {
    INFO("joint " << j);
    CHECK(first.keypoints[j].x == Approx(pb[j].x / 16.f).margin(1e-5));
    CHECK(first.keypoints[j].y == Approx(pb[j].y / 16.f).margin(1e-5));
    CHECK(first.keypoints[j].score == Approx(sb[j]));
    CHECK(second.keypoints[j].x == Approx(pa[j].x / 16.f).margin(1e-5));
    CHECK(second.keypoints[j].y == Approx(pa[j].y / 16.f).margin(1e-5));
    CHECK(second.keypoints[j].score == Approx(sa[j]));
    sum_a += sa[j], sum_b += sb[j];
  }
  CHECK(first.score == Approx(sum_b / 17));
  CHECK(second.score == Approx(sum_a / 17));

  o.part_threshold = 0.92f;  // only B's wrist remains a root candidate
  CHECK(decodePoseNet(p, o).size() == 1);
  o.part_threshold = 0.5f;
  o.max_persons = 1;
  CHECK(decodePoseNet(p, o).size() == 1);
}

TEST_CASE("OpenPose decoding gives back the poses the maps were rendered from") {
  const cv::Size grid(40, 24);
  Poses truth(3);
  // Three people with sub-cell joint positions; the third lacks its left arm and legs.
  const float shape[kNumJoints][2] = {
      {0, 0},       {-0.8f, -0.6f}, {0.8f, -0.6f}, {-1.6f, 0},     {1.6f, 0},    {-2.4f, 3},
      {2.4f, 3},    {-3.3f, 6.1f},  {3.3f, 6.1f},  {-3.6f, 9.2f},  {3.6f, 9.2f}, {-1.5f, 9.5f},
      {1.5f, 9.5f}, {-1.7f, 13.5f}, {1.7f, 13.5f}, {-1.8f, 17.4f}, {1.8f, 17.4f}};
  const cv::Point2f origin[3] = {{6.3f, 2.4f}, {18.7f, 3.1f}, {31.2f, 2.2f}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < kNumJoints; ++j) {
      truth[i].keypoints[j] = {origin[i].x + shape[j][0] * (1 + 0.1f * i),
                               origin[i].y + shape[j][1], 1.f};
    }
  }
  for (int j : {kLeftElbow, kLeftWrist, kLeftKnee, kRightKnee, kLeftAnkle, kRightAnkle}) {
    truth[2].keypoints[j].score = 0.f;
  }
  OpenPoseDecodeOptions o;
  const cv::Mat beliefs = test::renderBeliefs(truth, grid, 1.f);
  const cv::Mat pafs = test::renderPafs(truth, o.limbs, grid, 1.f);
  Poses got = decodeOpenPose(beliefs, pafs, o);
  REQUIRE(got.size() == 3);
  std::sort(got.begin(), got.end(),
            [](const Pose& a, const Pose& b) { return a.keypoints[0].x < b.keypoints[0].x; });
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < kNumJoints; ++j) {
      INFO("person " << i << " joint " << j);
      const auto& t = truth[i].keypoints[j];
      const auto& k = got[i].keypoints[j];
      REQUIRE((k.score > 0.f) == (t.score > 0.f));
      if (t.score <= 0.f) continue;
      CHECK(k.x == Approx(t.x).margin(1e-3));
      CHECK(k.y == Approx(t.y).margin(1e-3));
    }
  }
  o.nms_threshold = 1.f;  // no peak can pass: nobody
  CHECK(decodeOpenPose(beliefs, pafs, o).empty());
}

TEST_CASE("OpenPose decoding checks the PAF channels against the limb list") {
  OpenPoseDecodeOptions o;
  o.limbs = {{kLeftShoulder, kLeftElbow}};
  REQUIRE_THROWS_WITH(decodeOpenPose(zeros(18, 8, 8), zeros(4, 8, 8), o),
                      Catch::Contains("expected 2 channels, got 4"));
  o.limbs = {{kLeftShoulder, 17}};
  REQUIRE_THROWS_WITH(decodeOpenPose(zeros(18, 8, 8), zeros(2, 8, 8), o),
                      Catch::Contains("limb (5, 17)"));
}
