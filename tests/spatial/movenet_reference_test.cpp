// The MoveNet decoder against MoveNet's own post-processing (the complete TF.js graph run in
// onnxruntime by reference/movenet_graph_reference.py), on the same raw heads. The reference
// files are generated, not shipped: the test skips unless $JOINTFLOW_MOVENET_REFERENCE names
// their folder.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "../test_env.hpp"
#include "jointflow/movenet_decoder.hpp"

using namespace jointflow;

// A developer's check against the original TF.js graph's own output, which needs TensorFlow to
// make (tests/spatial/reference/movenet_graph_reference.py): hidden from the default run, run by
// the suite spatial-reference, which skips without JOINTFLOW_MOVENET_REFERENCE.
TEST_CASE("MoveNet decoding equals the original graph's post-processing (K = 6)", "[.reference]") {
  const std::string dir = test::envOr("JOINTFLOW_MOVENET_REFERENCE", "");
  if (dir.empty())
    JF_SKIP(
        "set JOINTFLOW_MOVENET_REFERENCE to the output folder of "
        "tests/spatial/reference/movenet_graph_reference.py");
  JF_REQUIRE_PATH_OR_SKIP(dir);
  int cases = 0;
  for (const std::string c : {"f200_native", "f300_256", "f500_384"}) {
    INFO("case " << c);
    std::ifstream in(dir + "/heads_" + c + ".bin", std::ios::binary);
    REQUIRE(in);
    cv::Mat t[6];
    for (auto& m : t) {
      int dims[4];
      in.read(reinterpret_cast<char*>(dims), sizeof dims);
      m.create(4, dims, CV_32F);
      in.read(reinterpret_cast<char*>(m.data),
              static_cast<std::streamsize>(m.total() * sizeof(float)));
    }
    REQUIRE(in);
    const auto ref = nlohmann::json::parse(std::ifstream(dir + "/ref_" + c + ".json"));
    MoveNetDecodeOptions o;
    o.max_persons = 6;
    const Poses got = decodeMoveNet({t[0], t[1], t[2], t[3], t[4], t[5]}, o);
    REQUIRE(got.size() == ref["persons"].size());
    for (size_t i = 0; i < got.size(); ++i) {
      const auto& r = ref["persons"][i];
      CHECK(got[i].score == Approx(r["score"].get<float>()).margin(1e-6));
      CHECK(got[i].box.y == Approx(r["box"][0].get<float>()).margin(1e-4));
      CHECK(got[i].box.x == Approx(r["box"][1].get<float>()).margin(1e-4));
      CHECK(got[i].box.y + got[i].box.h == Approx(r["box"][2].get<float>()).margin(1e-4));
      CHECK(got[i].box.x + got[i].box.w == Approx(r["box"][3].get<float>()).margin(1e-4));
      for (int j = 0; j < kNumJoints; ++j) {
        INFO("person " << i << " joint " << j);
        CHECK(got[i].keypoints[j].x == Approx(r["keypoints"][j][0].get<float>()).margin(1e-4));
        CHECK(got[i].keypoints[j].y == Approx(r["keypoints"][j][1].get<float>()).margin(1e-4));
        CHECK(got[i].keypoints[j].score == Approx(r["keypoints"][j][2].get<float>()).margin(1e-6));
      }
    }
    ++cases;
  }
  CHECK(cases == 3);
}
