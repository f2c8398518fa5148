// The shipped TFF network (models/tff_movenet.onnx, trained by training/) as the C++ runtime uses
// it: it loads against MoveNet's 24 feature channels, and on a real frame whose copy is moved
// sideways (a camera pan, within what it was trained on) its field points along the motion of the
// people's joints and not against it.
#include <string>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/similarity.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tff_model.hpp"
#include "test_env.hpp"

using namespace jointflow;

TEST_CASE("shipped TFF model follows a camera pan on a real frame", "[training]") {
  const std::string model_path = test::modelsDir() + "/tff_movenet.onnx";
  JF_REQUIRE_PATH_OR_SKIP(model_path);
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  cv::VideoCapture video(test::vtestPath());
  video.set(cv::CAP_PROP_POS_FRAMES, 200);
  cv::Mat frame;
  REQUIRE(video.read(frame));

  SpatialOptions options;  // the run-time default max:640, the policy the network was trained at
  auto spatial = createSpatialModel(ModelType::kMoveNet, options);
  TemporalFlowModel tff(model_path, spatial->featureChannels());
  REQUIRE(tff.inputChannels() == 82);

  const float shift_px = 20.f;  // frame pixels, to the right
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, shift_px, 0, 1, 0);
  cv::Mat moved;
  cv::warpAffine(frame, moved, shift, frame.size());

  const SpatialResult a = spatial->estimate(frame);
  const SpatialResult b = spatial->estimate(moved);
  REQUIRE(tff.predict(a.features, a.beliefs).empty());  // no previous frame yet
  const cv::Mat field = tff.predict(b.features, b.beliefs);
  REQUIRE(field.dims == 4);
  REQUIRE(field.size[1] == 34);
  REQUIRE(field.size[2] == a.beliefs.size[2]);
  REQUIRE(field.size[3] == a.beliefs.size[3]);

  // Eq. 5 along each confident joint's true motion, and along the opposite one.
  double along = 0.0, against = 0.0;
  int joints = 0;
  for (const Pose& pose : a.poses) {
    for (int j = 0; j < kNumJoints; ++j) {
      const Keypoint& k = pose.keypoints[j];
      if (k.score < 0.3f || k.x + shift_px >= frame.cols) continue;
      const cv::Point2f from = a.grid_to_frame.toGrid({k.x, k.y});
      const cv::Point2f to = a.grid_to_frame.toGrid({k.x + shift_px, k.y});
      const cv::Point2f back = a.grid_to_frame.toGrid({k.x - shift_px, k.y});
      along += flowFieldAggregate(field, j, from, to, 10);
      against += flowFieldAggregate(field, j, from, back, 10);
      ++joints;
    }
  }
  REQUIRE(joints >= 10);
  along /= joints;
  against /= joints;
  INFO("mean E_aggr along the motion " << along << ", against it " << against << " over " << joints
                                       << " joints");
  CHECK(along > 0.2);
  CHECK(along > against + 0.3);
}
