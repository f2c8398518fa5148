// The C++ Temporal Flow Field renderer (paper Eq. 2-4) must produce exactly the targets the TFF
// network was trained on: tests/data/tff_render_vectors.json holds renderings by the Python
// renderer of training/ (training/make_tff_vectors.py), compared here within 1e-6.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jointflow/temporal_flow.hpp"
#include "test_env.hpp"

namespace {

nlohmann::json loadVectors() {
  const std::string path = jointflow::test::sourceRoot() + "/tests/data/tff_render_vectors.json";
  std::ifstream in(path);
  REQUIRE(in.good());
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("C++ TFF rendering equals the training renderer on the shared vectors", "[training]") {
  const nlohmann::json doc = loadVectors();
  const int num_joints = doc.at("num_joints").get<int>();
  const double tolerance = doc.at("tolerance").get<double>();
  REQUIRE(tolerance <= 1e-6);
  REQUIRE(doc.at("cases").size() >= 10);

  for (const auto& c : doc.at("cases")) {
    const std::string name = c.at("name").get<std::string>();
    SECTION(name) {
      const cv::Size grid(c.at("grid")[0].get<int>(), c.at("grid")[1].get<int>());
      std::vector<jointflow::JointMotion> motions;
      for (const auto& m : c.at("motions")) {
        jointflow::JointMotion jm;
        jm.joint = m.at("joint").get<int>();
        jm.from = {m.at("from")[0].get<float>(), m.at("from")[1].get<float>()};
        jm.to = {m.at("to")[0].get<float>(), m.at("to")[1].get<float>()};
        motions.push_back(jm);
      }
      const cv::Mat field =
          jointflow::renderTemporalFlowField(motions, num_joints, grid, c.at("sigma").get<float>());
      REQUIRE(field.type() == CV_32F);
      REQUIRE(field.dims == 4);
      REQUIRE(field.size[0] == 1);
      REQUIRE(field.size[1] == 2 * num_joints);
      REQUIRE(field.size[2] == grid.height);
      REQUIRE(field.size[3] == grid.width);

      const auto& expected = c.at("field");
      REQUIRE(expected.size() == field.total());
      const float* got = field.ptr<float>();
      double max_diff = 0.0;
      size_t nonzero = 0;
      for (size_t i = 0; i < expected.size(); ++i) {
        const double e = expected[i].get<double>();
        max_diff = std::max(max_diff, std::abs(e - static_cast<double>(got[i])));
        nonzero += e != 0.0;
      }
      INFO(name << ": max abs diff " << max_diff << ", " << nonzero << " non-zero expected values");
      CHECK(max_diff <= tolerance);
    }
  }
}

TEST_CASE("shared TFF vectors exercise the cases the definition distinguishes", "[training]") {
  // Guards the vector file itself: a regenerated file that lost its edge cases would let a
  // renderer that ignores n(p), the inclusive borders or zero motion pass.
  const nlohmann::json doc = loadVectors();
  std::vector<std::string> names;
  for (const auto& c : doc.at("cases")) names.push_back(c.at("name").get<std::string>());
  for (const char* required :
       {"horizontal_inclusive_ends_and_width", "zero_motion_contributes_nothing",
        "two_people_crossing_average", "partly_outside_grid", "wide_sigma_subcell_motion"}) {
    CHECK(std::find(names.begin(), names.end(), required) != names.end());
  }
}
