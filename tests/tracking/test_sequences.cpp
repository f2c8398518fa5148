// Synthetic sequences where geometry fails and the flow field succeeds (paper, Sec. 4): two
// people crossing, a motion larger than a person's width, a camera pan. With an oracle TFF
// rendered from the ground truth the tracker recovers every identity exactly; OKS and IoU switch
// ids on the same detections.
#include <tuple>

#include <opencv2/imgproc.hpp>

#include <catch2/catch.hpp>

#include "synthetic.hpp"

using namespace jointflow;
using namespace jointflow::test;

namespace {

const cv::Size kFrame{960, 480};

// Two people cross at 80 px per frame (twice their width), 30 px apart vertically.
std::vector<GroundTruthFrame> crossing() {
  std::vector<GroundTruthFrame> frames;
  for (int t = 0; t < 6; ++t)
    frames.push_back({{1, standingPerson({120.f + 80.f * t, 250.f})},
                      {2, standingPerson({520.f - 80.f * t, 280.f})}});
  return frames;
}

// Two people walk in a row at 60 px per frame, 60 px apart: each frame the first lands where
// the second was.
std::vector<GroundTruthFrame> fastRow() {
  std::vector<GroundTruthFrame> frames;
  for (int t = 0; t < 8; ++t)
    frames.push_back({{1, standingPerson({100.f + 60.f * t, 250.f})},
                      {2, standingPerson({160.f + 60.f * t, 270.f})}});
  return frames;
}

// The camera pans 100 px per frame past three people standing 90 px apart.
std::vector<GroundTruthFrame> cameraPan(float pan = 100.f, float spacing = 90.f) {
  std::vector<GroundTruthFrame> frames;
  for (int t = 0; t < 5; ++t) {
    GroundTruthFrame f;
    for (int k = 0; k < 3; ++k)
      f[k + 1] = standingPerson({50.f + spacing * k + pan * t, 250.f + 20.f * (k % 2)});
    frames.push_back(f);
  }
  return frames;
}

// A smooth random texture 400 px wider than the frame, for a camera to pan over.
cv::Mat panTexture() {
  cv::Mat texture(kFrame.height, kFrame.width + 400, CV_8UC1);
  cv::RNG rng(11);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(texture, texture, {0, 0}, 3.0);
  cv::normalize(texture, texture, 0, 255, cv::NORM_MINMAX);
  return texture;
}

// Frame t of a pan whose scene content moves right by `step` px per frame: the window moves left.
cv::Mat panWindow(const cv::Mat& texture, size_t t, int step) {
  return texture(cv::Rect(400 - step * static_cast<int>(t), 0, kFrame.width, kFrame.height))
      .clone();
}

}  // namespace

TEST_CASE("an oracle TFF keeps every identity where OKS and IoU switch", "[tracking][sequence]") {
  const std::vector<std::pair<std::string, std::vector<GroundTruthFrame>>> sequences = {
      {"two people crossing", crossing()},
      {"motion larger than a person's width", fastRow()},
      {"camera pan", cameraPan()}};
  for (const auto& [name, frames] : sequences) {
    INFO(name);
    for (const Matcher matcher : {Matcher::kGreedy, Matcher::kOptimal}) {
      INFO(toString(matcher));
      TrackerSettings s = settingsFor("tff");
      s.matcher = matcher;
      PoseAssociator tff(s);
      const IdentityReport flow_field = runSequence(tff, frames, kFrame, true);
      CHECK(flow_field.exact);
      CHECK(flow_field.id_switches == 0);
    }
    for (const std::string similarity : {"oks", "iou"}) {
      INFO(similarity);
      PoseAssociator geometric(settingsFor(similarity));
      const IdentityReport r = runSequence(geometric, frames, kFrame, false);
      CHECK_FALSE(r.exact);
      CHECK(r.id_switches > 0);
    }
  }
}

TEST_CASE("a TFF with the motions swapped makes the tracker swap: the field decides",
          "[tracking][sequence]") {
  // The same crossing, but the field rendered as if the two had bounced back: the tracker must
  // follow the field, not the geometry.
  const auto frames = crossing();
  PoseAssociator a(settingsFor("tff"));
  int swapped = 0;
  for (size_t t = 0; t < frames.size(); ++t) {
    AssociationFrame in;
    in.grid_to_frame = oracleGrid();
    for (const auto& [id, pose] : frames[t]) in.poses.push_back(pose);
    if (t > 0) {
      GroundTruthFrame bounced = frames[t];
      std::swap(bounced[1], bounced[2]);
      in.tff = oracleTff(frames[t - 1], t == 3 ? bounced : frames[t], kFrame);
    }
    const auto out = a.update(in);
    REQUIRE(out.size() == 2);
    swapped += t >= 3 && out[0].track_id == 2;
  }
  CHECK(swapped == 3);  // swapped in frame 3 and kept so
}

TEST_CASE("similarity auto: oks between close frames, the TFF between frames further apart",
          "[tracking][sequence]") {
  // Two people walk in a row, each landing where the other was: oks switches them, the field
  // keeps them. auto asks for the field (FrameMotion::tff, as the Tracker reads it) only where
  // the frames are auto_tff_gap or more apart; closer, the network only keeps the maps and the ids
  // are oks's.
  const auto frames = fastRow();
  for (const double gap : {1.0 / 30, 0.5}) {
    INFO("frames " << gap << " s apart");
    const TrackerSettings s = settingsFor("auto");
    REQUIRE(s.auto_tff_gap == Approx(0.15f));
    PoseAssociator a(s);
    int runs = 0, keeps = 0;
    const IdentityReport r =
        runSequence(a, frames, kFrame, false, nullptr, [&](size_t t, AssociationFrame& in) {
          in.time = static_cast<double>(t) * gap;
          in.motion = a.estimateMotion(in);
          (in.motion->tff ? runs : keeps) += 1;
          if (in.motion->tff && t > 0) {
            in.tff = oracleTff(frames[t - 1], frames[t], kFrame);
            in.tff_camera_compensated = true;
          }
        });
    const bool far = gap >= s.auto_tff_gap;
    CHECK(runs == (far ? static_cast<int>(frames.size()) - 1 : 0));
    CHECK(keeps == (far ? 1 : static_cast<int>(frames.size())));  // far: the first frame only
    CHECK(r.exact == far);
    CHECK((r.id_switches == 0) == far);
    // oks on the same frames at the same times switches at either gap: what auto keeps between
    // frames far apart, the field kept.
    PoseAssociator oks(settingsFor("oks"));
    CHECK(runSequence(oks, frames, kFrame, false, nullptr, [&](size_t t, AssociationFrame& in) {
            in.time = static_cast<double>(t) * gap;
          }).id_switches > 0);
  }
}

TEST_CASE("tff's flow mix: where the field says nothing, the image's motion keeps the ids",
          "[tracking][sequence]") {
  // The textured scene of the pan below, three people 22 px apart part of it, frames 0.5 s apart
  // (a slow engine), camera compensation off (a camera thought fixed). The TFF is 0 everywhere, as
  // a network's field is for motions beyond its reach, so the mix has the prediction's OKS, which
  // stays behind and confuses the people, and the frames' flow, which follows them.
  const cv::Mat texture = panTexture();
  const auto frames = cameraPan(24.f, 22.f);
  const cv::Mat no_field =
      renderTemporalFlowField({}, kNumJoints, {kFrame.width / 4, kFrame.height / 4}, 1.f);
  // The flow joins the mix only between frames auto_tff_gap (0.15 s) or more apart.
  for (const auto& [flow_weight, gap] : {std::pair{0.25f, 0.5}, {0.f, 0.5}, {0.25f, 1.0 / 30}}) {
    INFO("tff_flow_weight " << flow_weight << ", frames " << gap << " s apart");
    TrackerSettings s = settingsFor("tff");
    REQUIRE(s.tff_flow_weight == Approx(0.25f));  // the default
    s.tff_flow_weight = flow_weight;
    s.camera_compensation = false;
    PoseAssociator a(s);
    const IdentityReport r = runSequence(
        a, frames, kFrame, false, [&](size_t t) { return panWindow(texture, t, 24); },
        [&](size_t t, AssociationFrame& in) {
          in.time = static_cast<double>(t) * gap;
          if (t > 0) in.tff = no_field;
        });
    const bool flow = flow_weight > 0.f && gap >= s.auto_tff_gap;
    CHECK(r.exact == flow);
    CHECK((r.id_switches == 0) == flow);
  }
}

TEST_CASE("without a TFF between two frames the tracker falls back to OKS",
          "[tracking][sequence]") {
  PoseAssociator a(settingsFor("tff"));
  auto frame = [](cv::Point2f at) {
    AssociationFrame in;  // no tff
    in.poses = {standingPerson(at)};
    in.grid_to_frame = oracleGrid();
    return in;
  };
  a.update(frame({100, 200}));
  const auto out = a.update(frame({104, 200}));
  REQUIRE(out.size() == 1);
  CHECK(out[0].track_id == 1);
}

TEST_CASE("a camera pan in real images: flow follows it, oks with camera compensation too",
          "[tracking][sequence]") {
  // A textured scene pans 24 px per frame; three people 22 px apart are part of it. The flow
  // carries each joint along; the camera motion estimated from the frames moves every track's
  // prediction for oks; without that, oks confuses the people.
  const cv::Mat texture = panTexture();
  const auto frames = cameraPan(24.f, 22.f);
  for (const std::string similarity : {"flow", "oks", "oks-uncompensated"}) {
    INFO(similarity);
    const bool compensated = similarity != "oks-uncompensated";
    TrackerSettings s = settingsFor(compensated ? similarity : "oks");
    s.camera_compensation = compensated;
    PoseAssociator a(s);
    // Scene content moves right by 24 px per frame: the window moves left.
    const IdentityReport r =
        runSequence(a, frames, kFrame, false, [&](size_t t) { return panWindow(texture, t, 24); });
    CHECK(r.exact == compensated);
    CHECK((r.id_switches == 0) == compensated);
  }
}

TEST_CASE("standing people keep their tracks under jitter through the geometric fallback",
          "[tracking][sequence]") {
  // Two people stand still; the detector jitters their joints by 3 px, above tau_delta = 2 px.
  // The oracle TFF is 0 everywhere (nobody moves), so Psi is 0 and the paper's association starts
  // new tracks; the fallback re-associates them on OKS.
  std::vector<GroundTruthFrame> truth(
      6, {{1, standingPerson({100, 200})}, {2, standingPerson({300, 200})}});
  auto jittered = truth;
  for (size_t t = 0; t < jittered.size(); ++t)
    for (auto& [id, pose] : jittered[t])
      for (int j = 0; j < kNumJoints; ++j) pose.keypoints[j].x += (t + j) % 2 ? 3.f : -3.f;
  // tff_oks_weight mixes the prediction's OKS into the potential itself: no fallback needed.
  // Without grey frames there is no flow, and tff_flow_weight goes to OKS too.
  for (const auto& [fallback, oks_weight, flow_weight] :
       {std::tuple{true, 0.f, 0.f}, {false, 0.f, 0.f}, {false, 0.5f, 0.f}, {false, 0.f, 0.25f}}) {
    INFO("fallback " << fallback << ", tff_oks_weight " << oks_weight << ", tff_flow_weight "
                     << flow_weight);
    TrackerSettings s = settingsFor("tff");
    s.tau_delta = 2.f;  // the paper's, below the jitter
    s.geometric_fallback = fallback;
    s.tff_oks_weight = oks_weight;
    s.tff_flow_weight = flow_weight;
    PoseAssociator a(s);
    int switches = 0;
    std::map<int, std::int64_t> first;
    for (size_t t = 0; t < truth.size(); ++t) {
      AssociationFrame in;
      in.grid_to_frame = oracleGrid();
      for (const auto& [id, pose] : jittered[t]) in.poses.push_back(pose);
      if (t > 0) in.tff = oracleTff(truth[t - 1], truth[t], kFrame);
      for (const TrackedPose& tp : a.update(in)) {
        auto [it, inserted] = first.emplace(static_cast<int>(tp.detection) + 1, tp.track_id);
        switches += !inserted && it->second != tp.track_id;
      }
    }
    CHECK((switches == 0) == (fallback || oks_weight + flow_weight > 0.f));
  }
}
