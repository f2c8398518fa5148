// PoseTrack 2017 / 2018 reading and writing, including malformed files.
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>

#include "../test_env.hpp"
#include "jointflow/error.hpp"
#include "jointflow/posetrack.hpp"
#include "synthetic_posetrack.hpp"

using namespace jointflow;
using namespace jointflow::posetrack;

namespace {

std::string bonn18() {
  return test::dataDir() + "/bonn-posetrack/annotations/test/060470979_bonn_test.json";
}
std::string bonn17() {
  return test::dataDir() + "/bonn-posetrack/annotations-posetrack17/test/060470979_bonn_test.json";
}

Sequence twoPeople() {
  Sequence seq = test::syntheticSequence("000001_mpii_test", 2);
  for (auto& frame : seq.frames) {
    frame.people.push_back(test::syntheticPerson(3, 10, 50));
    frame.people.push_back(test::syntheticPerson(4, 200, 50));
  }
  seq.frames[1].people[0].joints[kPtNose]->score = 0.75;
  seq.frames[1].people[1].joints[kPtHeadTop].reset();
  seq.frames[0].ignore_regions.push_back(Polygon{{0, 5, 5}, {0, 0, 5}});
  return seq;
}

void requireSame(const Sequence& a, const Sequence& b, bool same_names = true) {
  REQUIRE(a.frames.size() == b.frames.size());
  for (std::size_t f = 0; f < a.frames.size(); ++f) {
    const Frame &fa = a.frames[f], &fb = b.frames[f];
    if (same_names) CHECK(fa.file_name == fb.file_name);
    CHECK(fa.ignore_regions.size() == fb.ignore_regions.size());
    REQUIRE(fa.people.size() == fb.people.size());
    for (std::size_t p = 0; p < fa.people.size(); ++p) {
      const Person &pa = fa.people[p], &pb = fb.people[p];
      CHECK(pa.track_id == pb.track_id);
      REQUIRE(pa.head_box.has_value() == pb.head_box.has_value());
      if (pa.head_box) CHECK(pa.head_box->x2 == Approx(pb.head_box->x2));
      for (int j = 0; j < kNumPoseTrackJoints; ++j) {
        REQUIRE(pa.joints[j].has_value() == pb.joints[j].has_value());
        if (!pa.joints[j]) continue;
        CHECK(pa.joints[j]->x == Approx(pb.joints[j]->x));
        CHECK(pa.joints[j]->y == Approx(pb.joints[j]->y));
      }
    }
  }
}

/// The message of the jointflow::Error that parsing `text` throws.
std::string parseError(const std::string& text) {
  try {
    parseSequence(text, "bad_seq.json");
  } catch (const Error& e) {
    return e.what();
  }
  FAIL("no jointflow::Error for: " << text);
  return {};
}

const char* kCategories =
    R"("categories": [{"name": "person", "keypoints": ["nose", "head_bottom", "head_top",
    "left_ear", "right_ear", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow",
    "left_wrist", "right_wrist", "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle",
    "right_ankle"]}])";

}  // namespace

TEST_CASE("both formats round-trip a sequence", "[eval][io]") {
  const Sequence seq = twoPeople();
  for (Format format : {Format::k2017, Format::k2018}) {
    const Sequence back = parseSequence(toJson(seq, format), "000001_mpii_test.json");
    CHECK(back.format == format);
    CHECK(back.name == "000001_mpii_test");
    requireSame(seq, back);
    CHECK(back.frames[1].people[0].joints[kPtNose]->score == Approx(0.75));
  }
}

TEST_CASE("the writer enforces poseval's track id rules", "[eval][io]") {
  Sequence seq = twoPeople();
  seq.frames[0].people[0].track_id = 1000;
  CHECK_THROWS_WITH(toJson(seq, Format::k2018), Catch::Contains("outside 0..999"));
  seq.frames[0].people[0].track_id = 4;
  CHECK_THROWS_WITH(toJson(seq, Format::k2017), Catch::Contains("appears twice"));
  seq.frames[0].people[0].track_id.reset();
  CHECK_THROWS_WITH(toJson(seq, Format::k2018), Catch::Contains("no track id"));
}

TEST_CASE("writeSequence and readSequence use files; folders list their JSON files", "[eval][io]") {
  const auto dir = std::filesystem::temp_directory_path() / "jointflow-eval-io-test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "000001_mpii_test.json").string();
  writeSequence(twoPeople(), path, Format::k2018);
  requireSame(twoPeople(), readSequence(path));
  CHECK(listSequenceFiles(dir.string()) == std::vector<std::string>{path});
  CHECK_THROWS_WITH(readSequence((dir / "absent.json").string()), Catch::Contains("absent.json"));
  CHECK_THROWS_WITH(listSequenceFiles((dir / "nothing").string()), Catch::Contains("nothing"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("malformed files name the file and the field", "[eval][io]") {
  // Truncated JSON.
  std::string msg = parseError(R"({"annolist": [{"image": [{"name": "a.jpg"}], "annorect": [)");
  CHECK_THAT(msg, Catch::Contains("bad_seq.json") && Catch::Contains("not valid JSON"));
  // Neither format.
  msg = parseError(R"({"frames": []})");
  CHECK_THAT(msg, Catch::Contains("bad_seq.json") && Catch::Contains("annolist"));
  // 2017: missing field, wrong type.
  msg = parseError(R"({"annolist": [{"image": [{"name": "a.jpg"}]}]})");
  CHECK_THAT(msg, Catch::Contains("bad_seq.json") && Catch::Contains("annolist[0].annorect") &&
                      Catch::Contains("missing"));
  msg = parseError(R"({"annolist": [{"image": [{"name": "a.jpg"}], "annorect": [{"track_id":
      [1], "annopoints": [{"point": [{"id": [3], "x": ["12"], "y": [4]}]}]}]}]})");
  CHECK_THAT(msg, Catch::Contains("annolist[0].annorect[0].annopoints[0].point[0].x[0]") &&
                      Catch::Contains("expected a number, got string"));
  msg = parseError(R"({"annolist": [{"image": [{"name": "a.jpg"}], "annorect": [{"track_id":
      [1], "annopoints": [{"point": [{"id": [15], "x": [1], "y": [4]}]}]}]}]})");
  CHECK_THAT(msg, Catch::Contains("point[0].id[0]") && Catch::Contains("0..14"));
  // 2018: missing field, wrong type, wrong length, dangling image id.
  const std::string image = R"("images": [{"file_name": "a/000000.jpg", "id": 5}], )";
  msg = parseError("{" + image + R"("annotations": [{"image_id": 5, "track_id": 1}], )" +
                   kCategories + "}");
  CHECK_THAT(msg, Catch::Contains("annotations[0].keypoints") && Catch::Contains("missing"));
  msg = parseError("{" + image + R"("annotations": [{"image_id": 5, "track_id": "one",
      "keypoints": []}], )" +
                   kCategories + "}");
  CHECK_THAT(msg, Catch::Contains("annotations[0].track_id") && Catch::Contains("integer"));
  msg = parseError("{" + image + R"("annotations": [{"image_id": 5, "track_id": 1,
      "keypoints": [1, 2, 1]}], )" +
                   kCategories + "}");
  CHECK_THAT(msg, Catch::Contains("annotations[0].keypoints") && Catch::Contains("51 numbers"));
  msg = parseError("{" + image + R"("annotations": [{"image_id": 6, "track_id": 1,
      "keypoints": []}], )" +
                   kCategories + "}");
  CHECK_THAT(msg, Catch::Contains("annotations[0].image_id"));
  msg = parseError("{" + image + R"("annotations": []})");
  CHECK_THAT(msg, Catch::Contains("bad_seq.json: categories") && Catch::Contains("missing"));
}

TEST_CASE("the Bonn ground truth reads the same from both formats", "[eval][io][data]") {
  JF_REQUIRE_PATH_OR_SKIP(bonn18());
  JF_REQUIRE_PATH_OR_SKIP(bonn17());
  const Sequence a = readSequence(bonn18()), b = readSequence(bonn17());
  CHECK(a.format == Format::k2018);
  CHECK(b.format == Format::k2017);
  REQUIRE(a.frames.size() == 41);
  requireSame(a, b, false);  // the 2017 file names its frames differently
  int joints = 0;
  for (const Person& p : a.frames[0].people) {
    CHECK_FALSE(p.joints[kPtNose].has_value());  // the Bonn data has no nose
    for (const auto& j : p.joints) joints += j ? 1 : 0;
  }
  CHECK(a.frames[0].people.size() == 4);
  CHECK(joints == 4 * 14);
}
