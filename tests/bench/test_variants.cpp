// The identity benchmark's video variants (bench/variants.hpp) are exact: a marked point of a
// synthetic frame shows, after the warp, where the moved ground truth says (< 0.5 px); joints
// under the bar or out of the frame leave the ground truth; timelines (strides, reversal,
// forward-backward play, drops) keep their bookkeeping. The Bonn cases are checked on the real
// frames where the data folder holds them.
#include <algorithm>
#include <filesystem>
#include <set>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <catch2/catch.hpp>

#include "test_env.hpp"
#include "variants.hpp"

using namespace jointflow;
using namespace jointflow::bench;
namespace pt = jointflow::posetrack;

namespace {

/// A black frame with one bright Gaussian spot (sigma 2.5 px) at a sub-pixel position.
cv::Mat spotImage(cv::Size size, cv::Point2d spot) {
  cv::Mat grey(size, CV_32F);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double d2 = (x - spot.x) * (x - spot.x) + (y - spot.y) * (y - spot.y);
      grey.at<float>(y, x) = static_cast<float>(250.0 * std::exp(-d2 / (2 * 2.5 * 2.5)));
    }
  cv::Mat out;
  grey.convertTo(out, CV_8U);
  cv::cvtColor(out, out, cv::COLOR_GRAY2BGR);
  return out;
}

/// Intensity-weighted centre of a frame whose only light is the spot.
cv::Point2d centroid(const cv::Mat& bgr) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  const cv::Moments m = cv::moments(grey);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

pt::Person personAt(std::int64_t id, const std::vector<cv::Point2d>& joints) {
  pt::Person p;
  p.track_id = id;
  for (size_t j = 0; j < joints.size(); ++j)
    p.joints[j] = pt::PoseTrackPoint{joints[j].x, joints[j].y, std::nullopt, 1};
  p.head_box = pt::HeadBox{joints[0].x - 10, joints[0].y - 15, joints[0].x + 10, joints[0].y + 15};
  return p;
}

}  // namespace

TEST_CASE("a marked point lands where the moved ground truth says, to < 0.5 px",
          "[bench][variants]") {
  const cv::Size size(640, 360);
  const cv::Point2d spot(201.3, 117.6), centre((size.width - 1) / 2.0, (size.height - 1) / 2.0);
  const cv::Mat source = spotImage(size, spot);
  pt::Frame gt;
  gt.people.push_back(personAt(1, {spot}));
  const std::vector<std::pair<const char*, cv::Matx23d>> warps = {
      {"identity", {1, 0, 0, 0, 1, 0}},
      {"shake", shakePath(3, 80, 11)[2]},
      {"pan", {1, 0, 140, 0, 1, 0}},
      {"zoom 1.8x", scaleAbout(centre, 1.8)},
      {"small 1/3", scaleAbout(centre, 1.0 / 3)},
      {"shrink and shift", {0.5, 0, 37.25, 0, 0.5, -12.5}},
  };
  for (const auto& [name, warp] : warps) {
    INFO(name);
    FrameRecipe r;
    r.warp = warp;
    r.occluder_begin = 0;  // a bar at the left edge, away from the spot
    r.occluder_end = 20;
    const cv::Mat out = renderFrame(source, r, size);
    REQUIRE(out.size() == size);
    const pt::Frame moved = transformGroundTruth(gt, r, size);
    REQUIRE(moved.people.size() == 1);
    const auto& joint = *moved.people[0].joints[0];
    // The bar is grey: take it out before measuring where the light is.
    cv::Mat measured = out.clone();
    measured(cv::Rect(0, 0, 20, size.height)).setTo(cv::Scalar::all(0));
    const cv::Point2d seen = centroid(measured);
    CHECK(std::hypot(seen.x - joint.x, seen.y - joint.y) < 0.5);
    // The head box moves and scales with the frame.
    const double scale = std::hypot(warp(0, 0), warp(1, 0));
    const auto& box = *moved.people[0].head_box;
    CHECK(box.x2 - box.x1 == Approx(20 * scale));
    CHECK(box.y2 - box.y1 == Approx(30 * scale));
  }
}

TEST_CASE("joints under the bar or out of the frame leave the ground truth", "[bench][variants]") {
  const cv::Size size(400, 300);
  FrameRecipe r;
  r.warp = {1, 0, 50, 0, 1, 0};  // 50 px to the right
  r.occluder_begin = 80;         // columns 80 .. 199, pixel area [79.5, 199.5)
  r.occluder_end = 200;
  pt::Frame gt;
  gt.people.push_back(personAt(1, {{40, 100}, {250, 100}, {360, 120}}));  // -> 90, 300, 410
  gt.people.push_back(personAt(2, {{60, 50}, {100, 60}}));                // -> 110, 150: hidden
  gt.people.push_back(personAt(3, {{29.4, 10}, {29.6, 20}}));             // -> 79.4, 79.6
  const pt::Frame out = transformGroundTruth(gt, r, size);
  REQUIRE(out.people.size() == 2);
  CHECK(*out.people[0].track_id == 1);
  CHECK_FALSE(out.people[0].joints[0].has_value());  // under the bar
  REQUIRE(out.people[0].joints[1].has_value());
  CHECK(out.people[0].joints[1]->x == 300.0);
  CHECK(out.people[0].joints[1]->y == 100.0);
  CHECK_FALSE(out.people[0].joints[2].has_value());  // out of the frame
  CHECK(*out.people[1].track_id == 3);
  CHECK(out.people[1].joints[0].has_value());  // 79.4: on pixel 79, left of the bar
  CHECK_FALSE(out.people[1].joints[1].has_value());

  // The rendered bar covers exactly its columns, the rest is the shifted source.
  cv::Mat source(size, CV_8UC3);
  cv::randu(source, 0, 255);
  const cv::Mat frame = renderFrame(source, r, size);
  CHECK(cv::countNonZero(frame.col(80).reshape(1) != kOccluderGrey) == 0);
  CHECK(cv::countNonZero(frame.col(199).reshape(1) != kOccluderGrey) == 0);
  CHECK(cv::norm(frame(cv::Rect(200, 0, 200, 300)), source(cv::Rect(150, 0, 200, 300)),
                 cv::NORM_INF) == 0);
  CHECK(cv::norm(frame(cv::Rect(0, 0, 50, 300)), cv::NORM_INF) == kBorderGrey);
}

TEST_CASE("timelines: strides, reversal, forward-backward play, drops", "[bench][variants]") {
  const auto s3 = stridedTimeline(41, 3);
  REQUIRE(s3.size() == 14);
  CHECK(s3.front() == 0);
  CHECK(s3.back() == 39);
  const auto rev = reversedTimeline(41);
  CHECK(rev.size() == 41);
  CHECK(rev.front() == 40);
  CHECK(rev.back() == 0);

  const auto pp = pingPongTimeline(41, 121);
  REQUIRE(pp.size() == 121);
  CHECK(pp[40] == 40);
  CHECK(pp[41] == 39);  // no frame shown twice at a turn
  CHECK(pp[80] == 0);
  CHECK(pp[81] == 1);
  CHECK(pp[120] == 40);
  for (size_t k = 1; k < pp.size(); ++k) CHECK(std::abs(pp[k] - pp[k - 1]) == 1);

  const auto kept = keptAfterDrops(121, 0.5, 2018);
  CHECK(kept == keptAfterDrops(121, 0.5, 2018));
  CHECK(kept != keptAfterDrops(121, 0.5, 7));
  CHECK(kept.front() == 0);
  for (size_t k = 1; k < kept.size(); ++k) CHECK(kept[k] > kept[k - 1]);
  CHECK(kept.size() > 121 * 0.35);
  CHECK(kept.size() < 121 * 0.65);
  CHECK(keptAfterDrops(50, 0.0, 1).size() == 50);

  // The variants built on them: the ground truth of output frame k is that of its source frame.
  pt::Sequence source;
  for (int f = 0; f < 41; ++f) {
    pt::Frame frame;
    frame.file_name = std::to_string(f);
    frame.people.push_back(personAt(1, {{100.0 + f, 100.0}}));
    source.frames.push_back(frame);
  }
  VariantOptions options;
  options.seed = 2018;
  const std::vector<Variant> variants = bonnVariants(41, {960, 540}, options);
  for (const Variant& v : variants) {
    INFO(v.name);
    const pt::Sequence gt = variantGroundTruth(source, v);
    REQUIRE(gt.frames.size() == v.frames.size());
    // A source frame shown twice (forward-backward play) is two images: the PoseTrack files of
    // identity-bench --predictions put each annotation on its image by id.
    std::set<std::int64_t> image_ids, frame_ids;
    for (const pt::Frame& f : gt.frames) {
      image_ids.insert(f.image_id);
      frame_ids.insert(f.frame_id);
    }
    CHECK(image_ids.size() == gt.frames.size());
    CHECK(frame_ids.size() == gt.frames.size());
    if (v.name == "reversed") CHECK(gt.frames[0].people[0].joints[0]->x == 140.0);
    if (v.name == "dropped") {
      std::vector<int> expected;
      for (int k : keptAfterDrops(121, 0.5, 2018)) expected.push_back(pp[static_cast<size_t>(k)]);
      std::vector<int> got;
      for (const FrameRecipe& r : v.frames) got.push_back(r.source);
      CHECK(got == expected);
      for (size_t k = 0; k < got.size(); ++k)
        CHECK(gt.frames[k].people[0].joints[0]->x == 100.0 + got[k]);
      // Behind a leaky queue the time of the dropped frames passes.
      const auto positions = keptAfterDrops(121, 0.5, 2018);
      for (size_t k = 0; k < v.frames.size(); ++k)
        CHECK(v.frames[k].time == Approx(positions[k] / options.fps));
    } else if (v.name.rfind("slow-s", 0) == 0) {
      // A slow engine behind a leaky queue: about one frame in s of the forward-backward play,
      // each gap s +- slow_jitter frames, whose time passes.
      const int s = std::stoi(v.name.substr(6));
      const auto play = pingPongTimeline(41, options.slow_frames);
      REQUIRE(v.frames.size() >= static_cast<size_t>(options.slow_frames / (s + 1)));
      REQUIRE(v.frames.size() <= static_cast<size_t>(options.slow_frames / (s - 1) + 1));
      CHECK(v.frames[0].time == 0.0);
      std::set<int> gaps;
      std::set<std::pair<int, int>> pairs;  // the distinct pairs of source frames it tracks
      for (size_t k = 0; k < v.frames.size(); ++k) {
        const double position = v.frames[k].time * options.fps;
        const auto p = static_cast<size_t>(std::lround(position));
        REQUIRE(position == Approx(static_cast<double>(p)));
        REQUIRE(p < play.size());
        CHECK(v.frames[k].source == play[p]);
        CHECK(gt.frames[k].people[0].joints[0]->x == 100.0 + v.frames[k].source);
        if (k == 0) continue;
        const int gap =
            static_cast<int>(std::lround((v.frames[k].time - v.frames[k - 1].time) * options.fps));
        CHECK(std::abs(gap - s) <= options.slow_jitter);
        gaps.insert(gap);
        pairs.insert({v.frames[k - 1].source, v.frames[k].source});
      }
      // Every gap the jitter allows occurs, and the tracker meets many pairs of frames, not the
      // few that exact gaps of s give in the sequence's period (1 in 10: 4 pairs, each way).
      CHECK(gaps.size() == static_cast<size_t>(2 * options.slow_jitter + 1));
      CHECK(pairs.size() >= 40);
    } else {
      for (size_t k = 0; k < v.frames.size(); ++k)
        CHECK(v.frames[k].time == Approx(k / options.fps));
    }
    if (v.name.rfind("fast-x", 0) == 0) {
      // Fast motion at the camera's rate: slow-sN's frames, 1 / fps apart (checked above).
      const std::string slow = "slow-s" + v.name.substr(6);
      const auto w = std::find_if(variants.begin(), variants.end(),
                                  [&](const Variant& u) { return u.name == slow; });
      REQUIRE(w != variants.end());
      REQUIRE(w->frames.size() == v.frames.size());
      for (size_t k = 0; k < v.frames.size(); ++k) CHECK(v.frames[k].source == w->frames[k].source);
    }
  }
}

TEST_CASE("camera paths and hidden episodes", "[bench][variants]") {
  const auto shake = shakePath(200, 80, 3);
  for (const cv::Matx23d& m : shake) {
    CHECK(m(0, 2) == std::round(m(0, 2)));  // whole pixels: the output is an exact copy
    CHECK(std::hypot(m(0, 2), m(1, 2)) == Approx(80).margin(1));
  }
  CHECK(meanStep(shake, {0, 0}) > 90);
  CHECK(meanStep(shake, {0, 0}) < 115);
  const auto pan = panPath(100, 240, 20);
  for (size_t k = 1; k < pan.size(); ++k) {
    CHECK(std::fabs(pan[k](0, 2)) <= 240);
    CHECK(std::fabs(pan[k](0, 2) - pan[k - 1](0, 2)) == 20);
  }
  const auto zoom = zoomPath(81, {480, 270}, 1.8);
  CHECK(zoom.front()(0, 0) == 1.0);
  CHECK(zoom.back()(0, 0) == Approx(1.8));
  CHECK(zoom.back()(0, 2) == Approx(480 * (1 - 1.8)));

  // A person standing at x 100 .. 140 under a 100 px bar moving 2 px per frame: fully hidden
  // while the bar begins in [41, 100], i.e. frames 71 .. 100.
  std::vector<pt::Frame> source(1);
  source[0].people.push_back(personAt(5, {{100, 50}, {120, 60}, {140, 70}}));
  Variant v{"bar", "", {400, 200}, {}};
  for (int k = 0; k < 200; ++k) {
    FrameRecipe r;
    r.occluder_begin = -100 + 2 * k;
    r.occluder_end = r.occluder_begin + 100;
    v.frames.push_back(r);
  }
  const auto episodes = hiddenEpisodes(source, v);
  REQUIRE(episodes.size() == 1);
  CHECK(episodes[0].track_id == 5);
  CHECK(episodes[0].first == 71);
  CHECK(episodes[0].last == 100);
}

TEST_CASE("the Bonn cases on the real frames", "[bench][variants][data]") {
  const std::string root = test::dataDir() + "/bonn-posetrack";
  const std::string gt_path = root + "/annotations/test/060470979_bonn_test.json";
  JF_REQUIRE_PATH_OR_SKIP(gt_path);
  const pt::Sequence source = pt::readSequence(gt_path);
  const cv::Mat first = cv::imread(root + "/" + source.frames[0].file_name, cv::IMREAD_COLOR);
  REQUIRE_FALSE(first.empty());
  const std::vector<Variant> variants =
      bonnVariants(static_cast<int>(source.frames.size()), first.size());
  std::set<std::string> names;
  for (const Variant& v : variants) {
    names.insert(v.name);
    INFO(v.name);
    const pt::Sequence gt = variantGroundTruth(source, v);
    CHECK(gt.frames.size() == v.frames.size());
    if (v.name == "shake") {
      // Whole-pixel shifts: around every moved joint the output is the source, pixel for pixel.
      for (size_t k = 0; k < 5; ++k) {
        const FrameRecipe& r = v.frames[k];
        const cv::Mat src = cv::imread(root + "/" + source.frames[r.source].file_name);
        const cv::Mat out = renderFrame(src, r, v.size);
        const pt::Frame& moved = gt.frames[k];
        for (const pt::Person& p : moved.people)
          for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
            if (!p.joints[j]) continue;
            const cv::Point q(cvRound(p.joints[j]->x), cvRound(p.joints[j]->y));
            const cv::Point s(q.x - static_cast<int>(r.warp(0, 2)),
                              q.y - static_cast<int>(r.warp(1, 2)));
            const cv::Rect patch(-2, -2, 5, 5);
            const cv::Rect in_out = (patch + q) & cv::Rect({}, v.size);
            const cv::Rect in_src = (patch + s) & cv::Rect({}, src.size());
            if (in_out.size() != patch.size() || in_src.size() != patch.size()) continue;
            CHECK(cv::norm(out(in_out), src(in_src), cv::NORM_INF) == 0);
          }
      }
    }
    if (v.name == "occluder") {
      // The bar hides people for up to about 2 s (30 frames/s), and everyone comes back.
      const auto episodes = hiddenEpisodes(source.frames, v);
      REQUIRE(episodes.size() >= 4);
      int longest = 0;
      for (const auto& e : episodes) longest = std::max(longest, e.frames());
      CHECK(longest >= 30);
      CHECK(longest <= 75);
    }
  }
  CHECK(names == std::set<std::string>{"still-s1", "still-s2", "still-s3", "reversed", "dropped",
                                       "slow-s6", "slow-s8", "slow-s10", "slow-s12", "slow-s16",
                                       "fast-x6", "fast-x8", "fast-x12", "shake", "pan", "zoom",
                                       "occluder", "small"});
}
