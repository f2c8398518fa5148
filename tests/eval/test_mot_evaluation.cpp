// MOTChallenge box evaluation: cases small enough to score by hand (CLEAR MOT, IDF1, HOTA), the
// MOT17 preprocessing, the files, and malformed input. tests/eval/test_mot_reference.py checks
// the same figures against py-motmetrics and TrackEval on larger random sequences.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/mot_evaluation.hpp"

using jointflow::Error;
using jointflow::HotaScores;
using jointflow::kHotaAlphas;
using namespace jointflow::mot;
namespace fs = std::filesystem;

namespace {

Box box(std::int64_t id, double x, double y, double w = 20, double h = 50) {
  Box b;
  b.id = id;
  b.x = x, b.y = y, b.w = w, b.h = h;
  return b;
}

Box groundTruth(std::int64_t id, double x, double y, int cls, int flag = 1, double vis = 1.0) {
  Box b = box(id, x, y);
  b.cls = cls, b.flag = flag, b.visibility = vis;
  return b;
}

/// A folder of its own, removed at the end.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    path = fs::temp_directory_path() / ("jointflow-mot-test-" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() { fs::remove_all(path); }
  fs::path write(const std::string& name, const std::string& text) const {
    fs::create_directories((path / name).parent_path());
    std::ofstream(path / name) << text;
    return path / name;
  }
};

}  // namespace

TEST_CASE("MOT evaluation: perfect predictions score 100 on every figure", "[mot]") {
  Frames gt(3), pred(3);
  for (int t = 0; t < 3; ++t) {
    gt[t] = {groundTruth(1, 10.0 + t, 10, 1), groundTruth(2, 100, 10.0 + t, 1)};
    pred[t] = {box(7, 10.0 + t, 10), box(8, 100, 10.0 + t)};
  }
  const MotScores s = evaluateSequence(gt, pred);
  const HotaScores h = s.hotaScores();
  CHECK(s.recall() == Approx(100));
  CHECK(s.precision() == Approx(100));
  CHECK(s.mota() == Approx(100));
  CHECK(s.motp() == Approx(100));
  CHECK(s.idf1() == Approx(100));
  CHECK(h.mean_hota == Approx(100));
  CHECK(h.loca == Approx(100));
  CHECK(s.gt_ids == 2);
  CHECK(s.pred_ids == 2);
}

TEST_CASE("MOT evaluation: two ids swapped for half the sequence", "[mot]") {
  // A and B are found in all 4 frames; their predicted ids exchange from frame 3 on.
  Frames gt(4), pred(4);
  for (int t = 0; t < 4; ++t) {
    gt[t] = {groundTruth(1, 0, 0, 1), groundTruth(2, 100, 0, 1)};
    const bool swapped = t >= 2;
    pred[t] = {box(swapped ? 2 : 1, 0, 0), box(swapped ? 1 : 2, 100, 0)};
  }
  const MotScores s = evaluateSequence(gt, pred);
  CHECK(s.clear.switches == 2);
  CHECK(s.mota() == Approx(75.0));  // 1 - 2 switches / 8 objects
  // Each id covers its person in 2 of 4 frames: IDTP 4, IDFP 4, IDFN 4.
  CHECK(s.idf1() == Approx(50.0));
  // Every pair of ids shares 2 of its 4 frames: alignment 2 / (4 + 4 - 2) for the matches, so
  // AssA = 1/3 with DetA = 1, HOTA = sqrt(1/3) at every alpha.
  const HotaScores h = s.hotaScores();
  CHECK(h.deta == Approx(100));
  CHECK(h.assa == Approx(100.0 / 3));
  CHECK(h.mean_hota == Approx(100.0 * std::sqrt(1.0 / 3)));
}

TEST_CASE("MOT evaluation: HOTA's thresholds on a box of known IoU", "[mot]") {
  Frames gt{{groundTruth(1, 0, 0, 1)}}, pred{{box(5, 0, 0, 20, 60)}};
  gt[0][0].w = 20, gt[0][0].h = 50;  // IoU = 1000 / 1200
  const MotScores s = evaluateSequence(gt, pred);
  const HotaScores h = s.hotaScores();
  // Matched at alpha 0.05 ... 0.80 (16 of 19), missed at 0.85, 0.90, 0.95.
  CHECK(h.mean_hota == Approx(100.0 * 16 / 19));
  for (int a = 0; a < kHotaAlphas; ++a) CHECK(h.hota[a] == Approx(a < 16 ? 100.0 : 0.0));
  // TrackEval's LocA is 1 at an alpha without a match.
  CHECK(h.loca == Approx(100.0 * (16 * (1000.0 / 1200) + 3) / 19));
  CHECK(s.motp() == Approx(100.0 * 1000 / 1200));
  CHECK(s.recall() == Approx(100));
}

TEST_CASE("MOT evaluation: distractors, flags and barely visible people", "[mot]") {
  // One pedestrian, one reflection (class 8), one pedestrian flagged 0, one pedestrian 30 %
  // visible; a prediction on each, and one on nothing.
  Frames gt{{groundTruth(1, 0, 0, 1), groundTruth(2, 100, 0, 8), groundTruth(3, 200, 0, 1, 0),
             groundTruth(4, 300, 0, 1, 1, 0.3)}};
  Frames pred{{box(1, 0, 0), box(2, 100, 0), box(3, 200, 0), box(4, 300, 0), box(5, 500, 0)}};
  SECTION("visible people only (default)") {
    const MotScores s = evaluateSequence(gt, pred);
    CHECK(s.gt_dets == 1);
    CHECK(s.pred_dets == 3);  // the reflection's and the barely visible person's are removed
    CHECK(s.clear.false_positives == 2);  // the flag-0 person's and the one on nothing
    CHECK(s.recall() == Approx(100));
  }
  SECTION("TrackEval's rule (min_visibility 0)") {
    MotEvalOptions o;
    o.min_visibility = 0;
    const MotScores s = evaluateSequence(gt, pred, o);
    CHECK(s.gt_dets == 2);
    CHECK(s.pred_dets == 4);
    CHECK(s.clear.false_positives == 2);
  }
  SECTION("predictions below min_score are dropped first") {
    MotEvalOptions o;
    pred[0][0].confidence = 0.2;
    o.min_score = 0.5;
    const MotScores s = evaluateSequence(gt, pred, o);
    CHECK(s.recall() == Approx(0));
  }
}

TEST_CASE("MOT evaluation: empty sides", "[mot]") {
  Frames gt{{groundTruth(1, 0, 0, 1)}, {}};
  const MotScores none = evaluateSequence(gt, Frames{});
  CHECK(none.recall() == Approx(0));
  CHECK(std::isnan(none.precision()));
  CHECK(none.hotaScores().mean_hota == Approx(0));
  const MotScores only_false = evaluateSequence(Frames{{}, {}}, Frames{{}, {box(3, 0, 0)}});
  CHECK(std::isnan(only_false.mota()));
  CHECK(only_false.clear.false_positives == 1);
}

TEST_CASE("MOT evaluation: the MOTChallenge layout, MOT text and JSON Lines", "[mot]") {
  ScratchDir dir;
  // Ground truth of 3 frames (img1 holds 3 files; seqinfo.ini says 600, as in MOT17-mini).
  dir.write("train/SEQ-A/gt/gt.txt",
            "1,1,10,10,20,50,1,1,1.0\n2,1,12,10,20,50,1,1,1.0\n3,1,14,10,20,50,1,1,1.0\n"
            "700,1,14,10,20,50,1,1,1.0\n");
  dir.write("train/SEQ-A/seqinfo.ini", "[Sequence]\nseqLength=600\n");
  for (int f = 1; f <= 3; ++f) dir.write("train/SEQ-A/img1/00000" + std::to_string(f) + ".jpg", "");
  const auto sequences = readGroundTruth(dir.path.string());
  REQUIRE(sequences.size() == 1);
  CHECK(sequences[0].name == "SEQ-A");
  CHECK(sequences[0].frames.size() == 3);

  SECTION("JSON Lines: frames from 0, all objects") {
    dir.write("pred/SEQ-A.jsonl",
              "{\"frame\":0,\"objects\":[{\"id\":4,\"confidence\":0.9,\"x\":10,\"y\":10,\"w\":20,"
              "\"h\":50}]}\n{\"frame\":1,\"objects\":[]}\n"
              "{\"frame\":2,\"objects\":[{\"id\":4,\"confidence\":0.9,\"x\":14,\"y\":10,\"w\":20,"
              "\"h\":50}]}\n");
    const MotEvalResult r = evaluateFiles(dir.path.string(), (dir.path / "pred").string());
    CHECK(r.combined.clear.detections() == 2);
    CHECK(r.combined.clear.misses == 1);
    CHECK(resultJson(r).find("\"SEQ-A\"") != std::string::npos);
  }
  SECTION("a detection file: rows without id (-1) are each their own") {
    const auto p = dir.write("det.txt", "1,-1,10,10,20,50,0.9\n1,-1,300,10,20,50,0.3\n"
                                        "2,-1,12,10,20,50,0.9\n9,-1,0,0,1,1,1\n");
    const Frames frames = readPredictions(p.string(), 3);
    REQUIRE(frames[0].size() == 2);
    CHECK(frames[0][0].id != frames[0][1].id);
    CHECK(frames[1][0].id != frames[0][0].id);
    CHECK(frames[2].empty());  // frame 9 is past the sequence
  }
  SECTION("a missing prediction file names the sequence") {
    fs::create_directories(dir.path / "empty");
    CHECK_THROWS_WITH(evaluateFiles(dir.path.string(), (dir.path / "empty").string()),
                      Catch::Contains("SEQ-A"));
  }
}

TEST_CASE("MOT evaluation: malformed files are refused, naming file and line", "[mot]") {
  ScratchDir dir;
  CHECK_THROWS_WITH(readPredictions(dir.write("a.txt", "1,2,3\n").string(), 5),
                    Catch::Contains("a.txt:1") && Catch::Contains("6 columns"));
  CHECK_THROWS_WITH(readPredictions(dir.write("b.txt", "1,2,3,4,5,6\n1,x,3,4,5,6\n").string(), 5),
                    Catch::Contains("b.txt:2") && Catch::Contains("'x'"));
  CHECK_THROWS_WITH(readPredictions(dir.write("c.txt", "1,2,3,4,5,6\n1,2,3,4,5,6\n").string(), 5),
                    Catch::Contains("id 2 appears twice in frame 1"));
  CHECK_THROWS_WITH(readPredictions(dir.write("d.txt", "0,2,3,4,5,6\n").string(), 5),
                    Catch::Contains("integer >= 1"));
  CHECK_THROWS_WITH(readPredictions(dir.write("e.txt", "1,2,3,4,-5,6\n").string(), 5),
                    Catch::Contains("negative"));
  CHECK_THROWS_WITH(readPredictions(dir.write("f.jsonl", "{\"frame\":0,\"objects\":[{\"id\":1}\n")
                                        .string(),
                                    5),
                    Catch::Contains("f.jsonl:1") && Catch::Contains("not JSON"));
  CHECK_THROWS_WITH(readPredictions(dir.write("g.jsonl", "{\"frame\":0,\"objects\":[{\"id\":1}]}\n")
                                        .string(),
                                    5),
                    Catch::Contains("\"x\""));
  CHECK_THROWS_WITH(readGroundTruth((dir.path / "nothing").string()), Catch::Contains("no such"));
  CHECK_THROWS_WITH(readGroundTruth(dir.path.string()), Catch::Contains("no MOTChallenge"));
  dir.write("S/gt/gt.txt", "1,1,10,10,20,50,1,1\n");
  CHECK_THROWS_WITH(readGroundTruth(dir.path.string()), Catch::Contains("9 columns"));
}
