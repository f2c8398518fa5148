// Appearance descriptors for re-identification: people partly seen are compared on what shows.
#include <catch2/catch.hpp>

#include "jointflow/appearance.hpp"
#include "synthetic.hpp"

using namespace jointflow;
using namespace jointflow::test;

namespace {

// Two people, 300 px apart, each with a look of their own in an 8-channel feature map (stride 4)
// and in colour (red and blue clothes on a grey frame).
struct Scene {
  cv::Size frame{640, 480};
  GridTransform grid{4.f, 4.f, 0.f, 0.f};
  cv::Rect left{140, 120, 120, 220}, right{440, 120, 120, 220};
  cv::Mat features, bgr;
  JointThresholds thresholds{};

  Scene() {
    const int sizes[] = {1, 8, frame.height / 4, frame.width / 4};
    features = cv::Mat(4, sizes, CV_32F, cv::Scalar(0));
    for (int c = 0; c < 8; ++c) {
      cv::Mat plane(sizes[2], sizes[3], CV_32F, features.ptr<float>(0, c));
      const cv::Rect& r = c < 4 ? left : right;
      plane(cv::Rect(r.x / 4, r.y / 4, r.width / 4, r.height / 4)).setTo(1.f + c % 4);
    }
    bgr = cv::Mat(frame, CV_8UC3, cv::Scalar(90, 90, 90));
    bgr(left).setTo(cv::Scalar(30, 30, 200));
    bgr(right).setTo(cv::Scalar(200, 60, 30));
    thresholds.fill(0.3f);
  }

  Descriptor describe(const Pose& p, AppearanceModel model = AppearanceModel::kFeaturesColour) {
    return describeAppearance({p}, {0}, features, grid, bgr, thresholds, model).front();
  }
};

// The person at `hips` with the knees and ankles not detected (under an occluder).
Pose legsHidden(cv::Point2f hips) {
  Pose p = standingPerson(hips);
  for (int j : {kLeftKnee, kRightKnee, kLeftAnkle, kRightAnkle}) p.keypoints[j].score = 0.f;
  return p;
}

}  // namespace

TEST_CASE("a person with the legs hidden is re-identified on what shows", "[tracking][reid]") {
  Scene s;
  const cv::Point2f a(200, 250), b(500, 250);
  for (AppearanceModel model : {AppearanceModel::kFeatures, AppearanceModel::kFeaturesColour}) {
    INFO(toString(model));
    const Descriptor whole = s.describe(standingPerson(a), model);
    const Descriptor half = s.describe(legsHidden(a), model);
    REQUIRE_FALSE(whole.empty());
    REQUIRE_FALSE(half.empty());
    // The same person, whole and half hidden: alike (one vector with zeros for the legs scored
    // 0.82 in features and 0.71 in colour at best, under reid_min_similarity 0.8).
    CHECK(appearanceSimilarity(whole, half) > 0.99f);
  }
  // Told apart by colour: the other person, half hidden, is not alike.
  const Descriptor whole = s.describe(standingPerson(a));
  CHECK(appearanceSimilarity(whole, s.describe(legsHidden(b))) < 0.6f);
  CHECK(appearanceSimilarity(whole, s.describe(standingPerson(b))) < 0.6f);
}

TEST_CASE("without a part seen in both, appearance cannot tell", "[tracking][reid]") {
  Scene s;
  // Only the legs of one, only the head and arms of the other: no feature part in common... the
  // hips belong to the legs, so hide them too.
  Pose legs = standingPerson({200, 250}), top = standingPerson({200, 250});
  for (int j = 0; j <= kRightWrist; ++j) legs.keypoints[j].score = 0.f;
  for (int j = kLeftHip; j <= kRightAnkle; ++j) top.keypoints[j].score = 0.f;
  CHECK(appearanceSimilarity(s.describe(legs, AppearanceModel::kFeatures),
                             s.describe(top, AppearanceModel::kFeatures)) == 0.f);
  // With colour: the torso needs shoulders and hips, the legs hips and ankles; the top view has
  // no colour part, so features alone (which barely tell people apart) may not decide.
  CHECK(appearanceSimilarity(s.describe(standingPerson({200, 250})), s.describe(top)) == 0.f);
  // Descriptors of different models never match.
  CHECK(appearanceSimilarity(s.describe(standingPerson({200, 250}), AppearanceModel::kFeatures),
                             s.describe(standingPerson({200, 250}))) == 0.f);
}

TEST_CASE("a partial view leaves the parts it does not see as they were", "[tracking][reid]") {
  Scene s;
  Descriptor track = s.describe(standingPerson({200, 250}));
  const Descriptor before = track;
  // The other person's look, legs hidden, blended in: head, arms and torso move towards it, the
  // legs (feature part and colour) stay.
  blendAppearance(track, s.describe(legsHidden({500, 250})), 0.5f);
  CHECK(track.colour[1] == before.colour[1]);
  CHECK(track.colour[0] != before.colour[0]);
  CHECK(track.features[0] != before.features[0]);
  // An empty descriptor changes nothing; an empty track takes the new one.
  blendAppearance(track, Descriptor{}, 0.5f);
  CHECK(track.colour[1] == before.colour[1]);
  Descriptor none;
  blendAppearance(none, before, 0.9f);
  CHECK(appearanceSimilarity(none, before) > 0.999f);
}
