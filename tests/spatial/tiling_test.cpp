// Tiled inference (tiling.hpp): the layout of the tiles, the merge of their poses and the stitch of
// their maps, on exact synthetic input; and, on real frames, that tiles find more people.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "../test_env.hpp"
#include "../vtest_frame.hpp"
#include "jointflow/error.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tiling.hpp"
#include "jointflow/tracker.hpp"

using namespace jointflow;

namespace {

// A standing person: joints spread over the box (x, y, w, h), all scored `score`.
Pose person(float x, float y, float w, float h, float score) {
  Pose p;
  p.score = score;
  p.box = {x, y, w, h};
  for (int j = 0; j < kNumJoints; ++j) {
    const float fy = (j + 0.5f) / kNumJoints;  // head at the top, ankles at the bottom
    const float fx = j % 2 ? 0.3f : 0.7f;      // left and right
    p.keypoints[j] = {x + fx * w, y + fy * h, score};
  }
  return p;
}

// The part of `whole` a tile ending at x = `edge` sees: joints beyond it lost, the box cut there.
Pose cutAt(const Pose& whole, float edge, float score) {
  Pose p = whole;
  p.score = score;
  for (Keypoint& k : p.keypoints)
    if (k.x >= edge) k.score = 0.f;
  p.box.w = edge - p.box.x;
  return p;
}

}  // namespace

TEST_CASE("tileLayout: tiles of one size from border to border, overlapping at least as asked") {
  SECTION("1920x1080 in tiles of 512 at 0.2") {
    const auto tiles = tileLayout({1920, 1080}, 512, 0.2f);
    REQUIRE(tiles.size() == 15);  // 5 columns (step at most 409.6), 3 rows
    const int xs[] = {0, 352, 704, 1056, 1408};
    const int ys[] = {0, 284, 568};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 5; ++c) CHECK(tiles[r * 5 + c] == cv::Rect(xs[c], ys[r], 512, 512));
  }
  SECTION("an exact fit keeps its count") {
    const auto tiles = tileLayout({1280, 512}, 512, 0.25f);  // step 384: 0, 384, 768
    REQUIRE(tiles.size() == 3);
    CHECK(tiles[1] == cv::Rect(384, 0, 512, 512));
    CHECK(tiles[2] == cv::Rect(768, 0, 512, 512));
  }
  SECTION("overlap 0: tiles that touch") {
    const auto tiles = tileLayout({1024, 512}, 512, 0.f);
    REQUIRE(tiles.size() == 2);
    CHECK(tiles[1] == cv::Rect(512, 0, 512, 512));
  }
  SECTION("a frame smaller than a tile is one tile of its own size") {
    const auto tiles = tileLayout({300, 200}, 512, 0.2f);
    REQUIRE(tiles.size() == 1);
    CHECK(tiles[0] == cv::Rect(0, 0, 300, 200));
    CHECK(tileLayout({16, 16}, 512, 0.2f) == std::vector<cv::Rect>{{0, 0, 16, 16}});
  }
  SECTION("an axis shorter than a tile is one row") {
    const auto tiles = tileLayout({1000, 300}, 512, 0.2f);
    REQUIRE(tiles.size() == 3);
    CHECK(tiles[0] == cv::Rect(0, 0, 512, 300));
    CHECK(tiles[1] == cv::Rect(244, 0, 512, 300));
    CHECK(tiles[2] == cv::Rect(488, 0, 512, 300));
  }
  SECTION("any frame: inside it, covering it, neighbours sharing >= overlap x size") {
    for (const cv::Size frame : {cv::Size(640, 480), cv::Size(768, 576), cv::Size(1920, 1080),
                                 cv::Size(513, 2000), cv::Size(33, 700)})
      for (int size : {128, 384, 512})
        for (float overlap : {0.f, 0.15f, 0.25f, 0.5f}) {
          INFO(frame << " size " << size << " overlap " << overlap);
          const auto tiles = tileLayout(frame, size, overlap);
          cv::Mat covered(frame, CV_8U, cv::Scalar(0));
          for (const cv::Rect& t : tiles) {
            CHECK((t & cv::Rect({0, 0}, frame)) == t);
            CHECK(t.size() == tiles.front().size());
            covered(t).setTo(1);
          }
          CHECK(cv::countNonZero(covered) == frame.area());
          for (size_t i = 1; i < tiles.size(); ++i) {
            const cv::Rect& a = tiles[i - 1];
            const cv::Rect& b = tiles[i];
            if (a.y != b.y) continue;  // a new row
            CHECK(a.x + a.width - b.x >= overlap * size - 1);
          }
        }
  }
  SECTION("nonsense is refused") {
    CHECK_THROWS_AS(tileLayout({640, 480}, 0, 0.2f), Error);
    CHECK_THROWS_AS(tileLayout({640, 480}, 512, 0.6f), Error);
    CHECK_THROWS_AS(tileLayout({640, 480}, 512, std::nanf("")), Error);
  }
}

TEST_CASE("innerBorderMargin counts only the borders of a tile that lie inside the frame") {
  const cv::Size frame(912, 512);
  const cv::Rect left(0, 0, 512, 512), right(400, 0, 512, 512);
  CHECK(innerBorderMargin({100, 100, 50, 50}, left, frame) == 362.f);  // to x = 512
  CHECK(innerBorderMargin({480, 0, 40, 50}, left, frame) == -8.f);     // past it
  CHECK(innerBorderMargin({0, 0, 20, 512}, left, frame) == 492.f);     // frame borders: none
  CHECK(innerBorderMargin({850, 10, 62, 50}, right, frame) == 450.f);  // to x = 400
  CHECK(std::isinf(innerBorderMargin({0, 0, 912, 512}, {{0, 0}, frame}, frame)));
}

TEST_CASE("mergeTileRuns: a person cut by a tile border is kept from the tile that saw all of it") {
  const cv::Size frame(912, 512);
  const cv::Rect left(0, 0, 512, 512), right(400, 0, 512, 512);
  const Pose whole = person(480, 100, 80, 200, 0.5f);
  // The left tile sees the person up to its border at x = 512, with a higher score.
  TileRun a{left, 4.f, {cutAt(whole, 512, 0.7f)}};
  TileRun b{right, 4.f, {whole}};
  for (bool swapped : {false, true}) {
    const std::vector<TileRun> runs = swapped ? std::vector<TileRun>{b, a} : std::vector{a, b};
    const Poses merged = mergeTileRuns(runs, frame, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].box.w == 80.f);
    CHECK(merged[0].score == 0.5f);
  }
  SECTION("a part that shares no joint with the whole, inside its box, is dropped too") {
    Pose part = whole;
    for (Keypoint& k : part.keypoints) k.score = 0.f;
    part.box = {480, 100, 32, 100};
    const Poses merged = mergeTileRuns({{left, 4.f, {part}}, b}, frame, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].box.w == 80.f);
  }
  SECTION("cut in both tiles: the view that holds the most of the person") {
    // A person 300 to 800 px wide; the left tile ends at 700 (box centre 500, 200 px in), the
    // right one spans 500 to 1100 (box centre 650, 150 px in) and scores higher.
    const cv::Size wide(1200, 512);
    const Pose big = person(300, 0, 500, 512, 0.6f);
    const cv::Rect l(0, 0, 700, 512), r(500, 0, 600, 512);
    const Pose seen_left = cutAt(big, 700, 0.6f);
    Pose seen_right = big;
    seen_right.score = 0.9f;
    seen_right.box = {500, 0, 300, 512};
    for (Keypoint& k : seen_right.keypoints)
      if (k.x < 500) k.score = 0.f;
    const Poses merged = mergeTileRuns({{l, 4.f, {seen_left}}, {r, 4.f, {seen_right}}}, wide, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].box.x == 300.f);
    CHECK(merged[0].score == 0.6f);
  }
}

TEST_CASE("mergeTileRuns: second views are removed, distinct people and one run's poses kept") {
  const cv::Size frame(912, 512);
  const cv::Rect left(0, 0, 512, 512), right(400, 0, 512, 512);
  SECTION("one person inside both tiles: the higher score") {
    Pose one = person(420, 100, 60, 150, 0.6f);
    Pose two = one;
    two.score = 0.8f;
    for (Keypoint& k : two.keypoints) k.x += 2.f;  // a little apart, as two runs place them
    two.box.x += 2.f;
    const Poses merged = mergeTileRuns({{left, 4.f, {one}}, {right, 4.f, {two}}}, frame, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].score == 0.8f);
  }
  SECTION("two people whose boxes overlap, in two runs, are both kept") {
    const Pose front = person(420, 100, 60, 150, 0.6f);
    Pose behind = person(430, 100, 60, 150, 0.5f);
    for (Keypoint& k : behind.keypoints) k.y = 2 * 175.f - k.y;  // upside down: joints elsewhere
    const Poses merged = mergeTileRuns({{left, 4.f, {front}}, {right, 4.f, {behind}}}, frame, {});
    CHECK(merged.size() == 2);
  }
  SECTION("poses of one run are never merged") {
    const Pose p = person(100, 100, 60, 150, 0.6f);
    CHECK(mergeTileRuns({{left, 4.f, {p, p}}}, frame, {}).size() == 2);
  }
  SECTION("the full-frame run's whole person and a tile's part of it") {
    const Pose big = person(300, 20, 400, 480, 0.4f);
    const Poses merged = mergeTileRuns(
        {{{{0, 0}, frame}, 8.f, {big}}, {left, 4.f, {cutAt(big, 512, 0.9f)}}}, frame, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].box.w == 400.f);
  }
  SECTION("at most max_persons, the highest scores") {
    TileMergeOptions o;
    o.max_persons = 2;
    const Poses merged =
        mergeTileRuns({{left,
                        4.f,
                        {person(10, 10, 40, 90, 0.3f), person(100, 10, 40, 90, 0.9f),
                         person(200, 10, 40, 90, 0.6f)}}},
                      frame, o);
    REQUIRE(merged.size() == 2);
    CHECK(merged[0].score == 0.9f);
    CHECK(merged[1].score == 0.6f);
  }
}

TEST_CASE("mergeTileRuns: a cut pose that no other run saw is dropped") {
  // The left tile sees something at its border as part of a person; the right tile, which sees
  // the whole of it, and the whole frame find nobody there: a bag, a shadow (MOT17-mini: 8 such
  // poses, none a person).
  const cv::Size frame(912, 512);
  const cv::Rect left(0, 0, 512, 512), right(400, 0, 512, 512);
  const Pose thing = cutAt(person(470, 300, 60, 100, 0.4f), 512, 0.4f);
  const Pose elsewhere = person(700, 100, 60, 150, 0.6f);
  const TileRun whole_frame{{{0, 0}, frame}, 8.f, {}};
  SECTION("seen by one run: dropped") {
    const Poses merged =
        mergeTileRuns({whole_frame, {left, 4.f, {thing}}, {right, 4.f, {elsewhere}}}, frame, {});
    REQUIRE(merged.size() == 1);
    CHECK(merged[0].box.x == 700.f);
  }
  SECTION("seen by another run too: kept") {
    const Pose seen = person(470, 300, 60, 100, 0.3f);
    const Poses merged = mergeTileRuns(
        {whole_frame, {left, 4.f, {thing}}, {right, 4.f, {seen, elsewhere}}}, frame, {});
    REQUIRE(merged.size() == 2);
    CHECK(merged[1].box.x == 470.f);
  }
  SECTION("a whole pose seen by one run: kept (a small person only a tile sees)") {
    const Pose small = person(200, 300, 20, 50, 0.3f);
    CHECK(mergeTileRuns({whole_frame, {left, 4.f, {small}}}, frame, {}).size() == 1);
  }
}

TEST_CASE("mergeTileRuns: no pose outside the frame") {
  const cv::Size frame(640, 480);
  const cv::Rect tile(128, 0, 512, 480);      // at the right border: the network's padding beyond
  Pose p = person(600, 400, 80, 120, 0.7f);   // reaches 40 px past the right, 40 past the bottom
  Pose gone = person(650, 10, 30, 60, 0.9f);  // wholly in the padding
  const Poses merged = mergeTileRuns({{tile, 4.f, {p, gone}}}, frame, {});
  REQUIRE(merged.size() == 1);
  CHECK(merged[0].box.x == 600.f);
  CHECK(merged[0].box.x + merged[0].box.w == 640.f);
  CHECK(merged[0].box.y + merged[0].box.h == 480.f);
  for (const Keypoint& k : merged[0].keypoints) {
    CHECK(k.x >= 0.f);
    CHECK(k.x <= 639.f);
    CHECK(k.y <= 479.f);
  }
}

TEST_CASE("nearestTile: the tile where a point lies furthest from the borders") {
  const std::vector<cv::Rect> tiles{{0, 0, 512, 512}, {400, 0, 512, 512}};
  CHECK(nearestTile(tiles, {455.f, 255.f}) == 0);  // centres at x = 255.5 and 655.5
  CHECK(nearestTile(tiles, {456.f, 255.f}) == 1);
  // Nearer to the top than to either side: still the tile nearer in x.
  CHECK(nearestTile(tiles, {455.f, 10.f}) == 0);
  CHECK(nearestTile(tiles, {456.f, 10.f}) == 1);
  CHECK(nearestTile({}, {0.f, 0.f}) == -1);
}

TEST_CASE("stitchTileMaps: each cell from the nearest tile, sampled where the cell lies") {
  // Two tiles of 64x32 at x = 0 and 32 in a 96x32 frame, stride 4: tile grids of 16x8 cells, the
  // frame's of 24x8; cell c of the frame lies at x = 4c, cell c of the right tile at 32 + 4c.
  const cv::Size grid(24, 8);
  cv::Mat a(std::vector<int>{1, 2, 8, 16}, CV_32F), b(std::vector<int>{1, 2, 8, 16}, CV_32F);
  for (int ch = 0; ch < 2; ++ch)
    for (int r = 0; r < 8; ++r)
      for (int c = 0; c < 16; ++c) {
        a.ptr<float>(0, ch)[r * 16 + c] = static_cast<float>(c + 10 * ch);
        b.ptr<float>(0, ch)[r * 16 + c] = static_cast<float>(100 + c + 10 * ch);
      }
  const GridTransform frame_grid{4.f, 4.f, 0.f, 0.f};
  const GridTransform left{4.f, 4.f, 0.f, 0.f}, right{4.f, 4.f, 32.f, 0.f};
  const cv::Mat s =
      stitchTileMaps({a, b}, {left, right}, {{0, 0, 64, 32}, {32, 0, 64, 32}}, frame_grid, grid);
  REQUIRE(s.size[1] == 2);
  REQUIRE(s.size[2] == 8);
  REQUIRE(s.size[3] == 24);
  // The tiles' centres lie at x = 31.5 and 63.5: cells up to x = 44 (c = 11) take the left one.
  for (int ch = 0; ch < 2; ++ch)
    for (int c = 0; c < 24; ++c) {
      INFO("channel " << ch << " cell " << c);
      const float expected = c <= 11 ? c + 10.f * ch : 100.f + (c - 8) + 10.f * ch;
      CHECK(s.ptr<float>(0, ch)[3 * 24 + c] == Approx(expected));
    }
  CHECK_THROWS_AS(stitchTileMaps({}, {}, {}, frame_grid, grid), Error);
}

TEST_CASE("tile options out of range name the setting") {
  SpatialOptions o;
  o.tiles.mode = TileMode::kOn;
  CHECK_NOTHROW(validateSpatialOptions(o));
  o.tiles.size = 8;
  CHECK_THROWS_WITH(validateSpatialOptions(o), Catch::Contains("tile-size"));
  o.tiles.size = 512;
  o.tiles.overlap = 0.7f;
  CHECK_THROWS_WITH(validateSpatialOptions(o), Catch::Contains("tile-overlap"));
  o.tiles.overlap = 0.2f;
  o.tiles.scale = 0.f;
  CHECK_THROWS_WITH(validateSpatialOptions(o), Catch::Contains("tile-scale"));
  o.tiles.scale = 1.f;
  o.scales = {0.5f, 1.f};
  CHECK_THROWS_WITH(validateSpatialOptions(o), Catch::Contains("scales"));
  o.tiles.mode = TileMode::kOff;  // off: its values do not matter
  o.tiles.size = 8;
  CHECK_NOTHROW(validateSpatialOptions(o));
}

TEST_CASE("tiles=auto: tiles with MoveNet at one scale, none with several scales or PoseNet") {
  // What a user who sets nothing gets: the created model's options say what runs.
  SpatialOptions o;
  REQUIRE(o.tiles.mode == TileMode::kAuto);
  CHECK(createSpatialModel(ModelType::kAuto, o)->options().tiles.mode == TileMode::kOn);
  CHECK(createSpatialModel(ModelType::kPoseNet, o)->options().tiles.mode == TileMode::kOff);
  // The paper's multi-scale inference asks for no tiles, so auto gives it none (true is refused).
  o.scales = {0.5f, 1.f};
  CHECK(createSpatialModel(ModelType::kMoveNet, o)->options().tiles.mode == TileMode::kOff);
  o.tiles.mode = TileMode::kOn;
  CHECK_THROWS_WITH(createSpatialModel(ModelType::kMoveNet, o), Catch::Contains("scales"));
}

TEST_CASE("a frame that fits in one tile runs once: the poses of the whole frame alone") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  // 480x360 fits in one tile of 640, and max:640 already enlarges it: a tile would run the same
  // picture again. The poses are exactly those without tiles.
  cv::Mat frame;
  cv::resize(test::vtestFrame(200), frame, {480, 360}, 0, 0, cv::INTER_AREA);
  SpatialOptions o;
  o.tiles.mode = TileMode::kOn;
  auto tiled = createSpatialModel(ModelType::kMoveNet, o);
  const Poses with = tiled->estimate(frame).poses;
  CHECK(tiled->lastTimings().runs == 1);
  // vtest.avi's own 768x576: two tiles of 640 across and the whole frame.
  tiled->estimate(test::vtestFrame(200));
  CHECK(tiled->lastTimings().runs == 3);
  o.tiles.mode = TileMode::kOff;
  const Poses without = createSpatialModel(ModelType::kMoveNet, o)->estimate(frame).poses;
  REQUIRE(without.size() >= 5);
  REQUIRE(with.size() == without.size());
  for (size_t i = 0; i < with.size(); ++i)
    for (int j = 0; j < kNumJoints; ++j) {
      CHECK(with[i].keypoints[j].x == without[i].keypoints[j].x);
      CHECK(with[i].keypoints[j].y == without[i].keypoints[j].y);
    }
}

namespace {

// The MOT17 boxes of frame `frame` of a sequence that count as people: class 1, flag 1, at least
// half visible (MOT's own rule for pedestrians), as (x, y, w, h) with MOT's 1-based pixels moved
// to 0-based.
std::vector<Box> motPeople(const std::string& sequence, int frame) {
  std::ifstream in(sequence + "/gt/gt.txt");
  std::vector<Box> people;
  std::string line;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<float> v;
    std::string cell;
    while (std::getline(row, cell, ',')) v.push_back(std::stof(cell));
    if (v.size() >= 9 && static_cast<int>(v[0]) == frame && v[6] == 1.f && v[7] == 1.f &&
        v[8] >= 0.5f)
      people.push_back({v[2] - 1.f, v[3] - 1.f, v[4], v[5]});
  }
  return people;
}

// People whose box a pose's box overlaps at IoU >= 0.5, each pose counted once (greedy by IoU).
int found(const std::vector<Box>& people, const Poses& poses) {
  std::vector<bool> used(poses.size());
  int n = 0;
  for (const Box& b : people) {
    int best = -1;
    float best_iou = 0.5f;
    for (size_t i = 0; i < poses.size(); ++i)
      if (!used[i] && iou(b, poses[i].box) >= best_iou) best_iou = iou(b, poses[i].box), best = i;
    if (best >= 0) used[best] = true, ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("tiles on tiny frames and at the frame's borders: no error, no pose outside") {
  SpatialOptions o;
  o.tiles.mode = TileMode::kOn;
  o.tiles.size = 64;
  o.tiles.scale = 2.f;
  for (bool full_frame : {true, false}) {
    o.tiles.full_frame = full_frame;
    auto model = createSpatialModel(ModelType::kMoveNet, o);
    for (const cv::Size size : {cv::Size(16, 16), cv::Size(20, 300), cv::Size(300, 20),
                                cv::Size(65, 129), cv::Size(200, 150)}) {
      INFO(size << (full_frame ? " with" : " without") << " the full frame");
      cv::Mat frame(size, CV_8UC3);
      cv::randu(frame, 0, 255);
      const SpatialResult r = model->estimate(frame);
      CHECK(r.frame_size == size);
      CHECK_FALSE(r.beliefs.empty());
      CHECK_FALSE(r.features.empty());
      for (const Pose& p : r.poses) {
        CHECK(p.box.x >= 0.f);
        CHECK(p.box.y >= 0.f);
        CHECK(p.box.x + p.box.w <= size.width);
        CHECK(p.box.y + p.box.h <= size.height);
        for (const Keypoint& k : p.keypoints) {
          CHECK(k.x >= 0.f);
          CHECK(k.y >= 0.f);
          CHECK(k.x <= size.width - 1.f);
          CHECK(k.y <= size.height - 1.f);
        }
      }
    }
    CHECK_THROWS_AS(model->estimate(cv::Mat(15, 40, CV_8UC3, cv::Scalar::all(0))), Error);
  }
}

TEST_CASE("tiles find more of the people of a street scene than the whole frame", "[data]") {
  const std::string sequence = test::dataDir() + "/mot17-mini/train/MOT17-04-FRCNN";
  JF_REQUIRE_PATH_OR_SKIP(sequence);
  const cv::Mat frame = cv::imread(sequence + "/img1/000001.jpg");
  REQUIRE_FALSE(frame.empty());
  const std::vector<Box> people = motPeople(sequence, 1);
  SpatialOptions o;
  o.tiles.mode = TileMode::kOff;
  auto whole = createSpatialModel(ModelType::kMoveNet, o);
  o.tiles.mode = TileMode::kOn;
  auto tiled = createSpatialModel(ModelType::kMoveNet, o);
  const SpatialResult a = whole->estimate(frame);
  const SpatialResult b = tiled->estimate(frame);
  const int without = found(people, a.poses), with = found(people, b.poses);
  WARN("MOT17-04 frame 1, " << people.size() << " people: " << without << " found at "
                            << o.input_size.toString() << ", " << with << " with tiles of "
                            << o.tiles.size << " (" << a.poses.size() << " and " << b.poses.size()
                            << " poses)");
  CHECK(with >= without + 5);
  CHECK(with >= static_cast<int>(0.7 * people.size()));
  // The TFF network's maps are the whole frame's, at max:640.
  CHECK(b.beliefs.size[3] == a.beliefs.size[3]);
  CHECK(b.grid_to_frame.scale_x == a.grid_to_frame.scale_x);
}

TEST_CASE("the TFF network tracks on the maps of tiles, with the whole frame and without") {
  JF_REQUIRE_PATH_OR_SKIP(test::vtestPath());
  cv::VideoCapture cap(test::vtestPath());
  cap.set(cv::CAP_PROP_POS_FRAMES, 200);  // 7 people
  std::vector<cv::Mat> frames(3);
  for (cv::Mat& f : frames) REQUIRE(cap.read(f));
  for (bool full_frame : {true, false}) {
    INFO((full_frame ? "the whole frame's maps" : "the tiles' maps stitched"));
    TrackerSettings s;
    s.similarity = SimilarityType::kTff;
    s.spatial.tiles.mode = TileMode::kOn;
    s.spatial.tiles.size = 384;
    s.spatial.tiles.full_frame = full_frame;
    Tracker tracker(s);
    REQUIRE(tracker.hasTff());
    std::set<std::int64_t> first;
    for (const TrackedPose& p : tracker.process(frames[0], PixelOrder::kBGR, 0.0))
      first.insert(p.track_id);
    tracker.process(frames[1], PixelOrder::kBGR, 0.1);
    const auto last = tracker.process(frames[2], PixelOrder::kBGR, 0.2);
    CHECK(first.size() >= 5);
    // People moved a few pixels: the TFF's potential keeps most of them on their tracks.
    const auto kept = std::count_if(last.begin(), last.end(), [&](const TrackedPose& p) {
      return first.count(p.track_id) > 0;
    });
    CHECK(kept >= static_cast<long>(first.size()) - 1);
  }
}
