// The TFF runner end to end on tiny ONNX networks of the contract that
// tests/tracking/make_tiny_tff.py generates (committed in tests/data/).
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/dnn.hpp>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/tff_model.hpp"
#include "test_env.hpp"

using namespace jointflow;

namespace {

const int kC = 3;  // feature channels of the tiny models

std::string dataFile(const std::string& name) {
  return jointflow::test::sourceRoot() + "/tests/data/" + name;
}

cv::Mat blob(int channels, int h, int w, float (*value)(int c, int y, int x)) {
  const int sizes[] = {1, channels, h, w};
  cv::Mat m(4, sizes, CV_32F);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int idx[] = {0, c, y, x};
        m.at<float>(idx) = value(c, y, x);
      }
  return m;
}

float at(const cv::Mat& m, int c, int y, int x) {
  const int idx[] = {0, c, y, x};
  return m.at<float>(idx);
}

// Distinct values per frame, map, channel and cell.
cv::Mat features(int frame, int h, int w) {
  cv::Mat m = blob(kC, h, w, [](int c, int y, int x) { return 0.1f * c + 0.01f * y + 0.001f * x; });
  return m + cv::Scalar(frame);
}
cv::Mat beliefs(int frame, int h, int w) {
  cv::Mat m = blob(17, h, w, [](int c, int y, int x) { return 0.03f * c + 0.002f * (y + x); });
  return m + cv::Scalar(0.5 * frame);
}

}  // namespace

TEST_CASE("TFF runner: channel contract and the one-frame state", "[tracking][tff_model]") {
  TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC);
  CHECK(model.inputChannels() == 40);
  const int h = 5, w = 7;
  CHECK(model.predict(features(1, h, w), beliefs(1, h, w)).empty());  // no previous frame yet
  CHECK(model.hasPrevious());
  for (int frame = 2; frame <= 3; ++frame) {
    // tff[2j] = beliefs(t)[j] + 10 features(t)[j % 3]; tff[2j+1] = the same of t-1.
    const cv::Mat tff = model.predict(features(frame, h, w), beliefs(frame, h, w));
    REQUIRE(tff.dims == 4);
    REQUIRE(tff.size[1] == 34);
    REQUIRE(tff.size[2] == h);
    REQUIRE(tff.size[3] == w);
    const cv::Mat fc = features(frame, h, w), bc = beliefs(frame, h, w);
    const cv::Mat fp = features(frame - 1, h, w), bp = beliefs(frame - 1, h, w);
    for (int j = 0; j < 17; ++j)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          CHECK(at(tff, 2 * j, y, x) == Approx(at(bc, j, y, x) + 10 * at(fc, j % kC, y, x)));
          CHECK(at(tff, 2 * j + 1, y, x) == Approx(at(bp, j, y, x) + 10 * at(fp, j % kC, y, x)));
        }
  }
  model.reset();
  CHECK_FALSE(model.hasPrevious());
  CHECK(model.predict(features(4, h, w), beliefs(4, h, w)).empty());
  // A new grid size starts over instead of pairing maps of two grids.
  CHECK(model.predict(features(5, h + 1, w), beliefs(5, h + 1, w)).empty());
  CHECK_FALSE(model.predict(features(6, h + 1, w), beliefs(6, h + 1, w)).empty());
}

TEST_CASE("TFF runner: remember() keeps a frame's maps for the next field without a run",
          "[tracking][tff_model]") {
  // similarity auto between close frames: the next field must pair with the frame remembered,
  // not with an older one.
  TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC);
  const int h = 5, w = 7;
  CHECK(model.predict(features(1, h, w), beliefs(1, h, w)).empty());
  model.remember(features(2, h, w), beliefs(2, h, w));
  const cv::Mat tff = model.predict(features(3, h, w), beliefs(3, h, w));
  REQUIRE_FALSE(tff.empty());
  // Channel 2j+1 holds the previous frame's beliefs(j) + 10 features(j % 3): frame 2's.
  const cv::Mat fp = features(2, h, w), bp = beliefs(2, h, w);
  for (int j = 0; j < 17; ++j)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        CHECK(at(tff, 2 * j + 1, y, x) == Approx(at(bp, j, y, x) + 10 * at(fp, j % kC, y, x)));
  // remember() checks the maps as predict() does.
  CHECK_THROWS_WITH(model.remember(features(4, h, w), beliefs(4, h + 1, w)),
                    Catch::Contains("belief map"));
}

TEST_CASE("TFF runner: the previous maps are moved by the camera motion before the network",
          "[tracking][tff_model]") {
  // The wiring model passes the previous maps through (tff[2j+1] = beliefs(t-1)[j] +
  // 10 features(t-1)[j % 3]), so its odd channels show exactly what the network was given. The
  // maps are linear in x and y, so bilinear sampling between cells is exact; 20 planes make
  // five groups of four in the runner's warp.
  const int h = 6, w = 9;
  for (const cv::Point2f shift : {cv::Point2f(2.f, 1.f), cv::Point2f(1.5f, -0.5f)}) {
    TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC);
    model.predict(features(1, h, w), beliefs(1, h, w));
    const cv::Matx23f camera(1, 0, shift.x, 0, 1, shift.y);
    const cv::Mat tff = model.predict(features(2, h, w), beliefs(2, h, w), camera);
    const cv::Mat fc = features(2, h, w), bc = beliefs(2, h, w);
    const cv::Mat fp = features(1, h, w), bp = beliefs(1, h, w);
    auto previous = [&](int j, float y, float x) {  // the linear maps, anywhere
      const float f = 1 + 0.1f * (j % kC) + 0.01f * y + 0.001f * x;
      const float b = 0.5f + 0.03f * j + 0.002f * (y + x);
      return b + 10 * f;
    };
    CHECK(previous(4, 2, 3) == Approx(at(bp, 4, 2, 3) + 10 * at(fp, 4 % kC, 2, 3)));
    for (int j = 0; j < 17; ++j)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          CHECK(at(tff, 2 * j, y, x) == Approx(at(bc, j, y, x) + 10 * at(fc, j % kC, y, x)));
          // Cell (x, y) now shows the previous frame's (x - shift.x, y - shift.y): bilinear
          // between its four cells, those outside the previous view counting 0.
          const float sx = x - shift.x, sy = y - shift.y;
          const int x0 = static_cast<int>(std::floor(sx)), y0 = static_cast<int>(std::floor(sy));
          float expected = 0.f;
          for (int dy : {0, 1})
            for (int dx : {0, 1}) {
              const int cx = x0 + dx, cy = y0 + dy;
              const float weight = (dx ? sx - x0 : 1 - (sx - x0)) * (dy ? sy - y0 : 1 - (sy - y0));
              if (cx >= 0 && cy >= 0 && cx < w && cy < h) expected += weight * previous(j, cy, cx);
            }
          CHECK(at(tff, 2 * j + 1, y, x) == Approx(expected).margin(1e-3));
        }
  }
}

TEST_CASE("TFF runner: a network of stride 2 gets the maps pooled 2x2, moved on its grid",
          "[tracking][tff_model]") {
  // The stride-2 wiring model copies each input cell's wiring output to 2x2 maps cells, so the
  // field shows exactly what the network was given: the mean of each 2x2 block of the maps (for
  // these maps, linear in x and y, their value at the block's centre (2q + 0.5)), the previous
  // ones moved by the camera on the pooled grid (half the motion in its cells: exact here).
  const int h = 8, w = 12;
  TemporalFlowModel model(dataFile("tff_wiring_stride2_c3.onnx"), kC);
  auto value = [](int frame, int j, float y, float x) {  // beliefs[j] + 10 features[j % 3]
    const float f = frame + 0.1f * (j % kC) + 0.01f * y + 0.001f * x;
    const float b = 0.5f * frame + 0.03f * j + 0.002f * (y + x);
    return b + 10 * f;
  };
  CHECK(value(2, 4, 2, 3) ==
        Approx(at(beliefs(2, h, w), 4, 2, 3) + 10 * at(features(2, h, w), 4 % kC, 2, 3)));
  CHECK(model.predict(features(1, h, w), beliefs(1, h, w)).empty());
  const cv::Matx23f camera(1, 0, 2.f, 0, 1, -1.f);  // maps cells: 1 and -0.5 pooled cells
  const cv::Mat tff = model.predict(features(2, h, w), beliefs(2, h, w), camera);
  REQUIRE(tff.dims == 4);
  REQUIRE(tff.size[2] == h);  // the field on the maps' grid
  REQUIRE(tff.size[3] == w);
  for (int j = 0; j < 17; ++j)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float cy = 2 * (y / 2) + 0.5f, cx = 2 * (x / 2) + 0.5f;  // the block's centre
        CHECK(at(tff, 2 * j, y, x) == Approx(value(2, j, cy, cx)));
        // Pooled cell (qx, qy) shows the previous pooled cell (qx - 1, qy + 0.5): inside the
        // previous view when qx >= 1 and qy + 1 <= h / 2 - 1.
        if (x / 2 >= 1 && y / 2 + 1 <= h / 2 - 1)
          CHECK(at(tff, 2 * j + 1, y, x) == Approx(value(1, j, cy + 1.f, cx - 2.f)).margin(1e-3));
      }
  // A grid of odd size runs on the nearest even one and the field comes back on its own.
  TemporalFlowModel odd(dataFile("tff_wiring_stride2_c3.onnx"), kC);
  odd.predict(features(1, 7, 9), beliefs(1, 7, 9));
  const cv::Mat field = odd.predict(features(2, 7, 9), beliefs(2, 7, 9));
  REQUIRE(field.dims == 4);
  CHECK(field.size[2] == 7);
  CHECK(field.size[3] == 9);
}

TEST_CASE("TFF runner: a camera motion in frame pixels expressed on the grid",
          "[tracking][tff_model]") {
  // Grid cell q -> frame p = S q + o; the frame motion m; back to the grid: the same as the
  // grid motion applied to q.
  const GridTransform g{4.f, 5.f, 6.f, -3.f};
  const float a = 1.02f * std::cos(0.03f), b = 1.02f * std::sin(0.03f);
  const cv::Matx23f m(a, -b, 12.f, b, a, -7.f);
  const cv::Matx23f on_grid = cameraMotionOnGrid(m, g);
  for (const cv::Point2f q : {cv::Point2f(0, 0), cv::Point2f(10, 3), cv::Point2f(-2, 7.5f)}) {
    const cv::Point2f p = g.toFrame(q);
    const cv::Point2f expected = g.toGrid(
        {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2), m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)});
    const cv::Point2f got(on_grid(0, 0) * q.x + on_grid(0, 1) * q.y + on_grid(0, 2),
                          on_grid(1, 0) * q.x + on_grid(1, 1) * q.y + on_grid(1, 2));
    CHECK(got.x == Approx(expected.x).margin(1e-4));
    CHECK(got.y == Approx(expected.y).margin(1e-4));
  }
  CHECK(cameraMotionOnGrid(cv::Matx23f(1, 0, 0, 0, 1, 0), g) == cv::Matx23f(1, 0, 0, 0, 1, 0));
}

TEST_CASE("TFF runner: with max_grid_side, larger grids run resampled, the field comes back",
          "[tracking][tff_model]") {
  CHECK(TemporalFlowModel(dataFile("tff_wiring_c3.onnx"), kC).maxGridSide() == 0);  // off
  CHECK_THROWS_WITH(TemporalFlowModel(dataFile("tff_wiring_c3.onnx"), kC, EngineOptions{}, -1),
                    Catch::Contains("max_grid_side"));
  // A 24 x 40 grid with max_grid_side 10 runs on 6 x 10 cells; maps constant per channel are
  // unchanged by the resampling both ways, so the field is the wiring model's exactly, on the
  // input grid.
  TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC, EngineOptions{}, 10);
  const int h = 24, w = 40;
  auto constant = [](int channels, int frame) {
    const int sizes[] = {1, channels, h, w};
    cv::Mat m(4, sizes, CV_32F);
    for (int c = 0; c < channels; ++c) m.reshape(1, channels).row(c).setTo(0.1f * c + frame);
    return m;
  };
  CHECK(model.predict(constant(kC, 1), constant(17, 1)).empty());
  const cv::Mat tff = model.predict(constant(kC, 2), constant(17, 2));
  REQUIRE(tff.dims == 4);
  REQUIRE(tff.size[2] == h);
  REQUIRE(tff.size[3] == w);
  for (int j = 0; j < 17; ++j)
    for (int y : {0, 11, 23})
      for (int x : {0, 17, 39}) {
        CHECK(at(tff, 2 * j, y, x) == Approx(0.1 * j + 2 + 10 * (0.1 * (j % kC) + 2)));
        CHECK(at(tff, 2 * j + 1, y, x) == Approx(0.1 * j + 1 + 10 * (0.1 * (j % kC) + 1)));
      }
}

TEST_CASE("TFF runner: the paper's architecture matches a numpy reference",
          "[tracking][tff_model]") {
  std::ifstream file(dataFile("tff_tiny_c3_expected.json"));
  REQUIRE(file.good());
  const nlohmann::json ref = nlohmann::json::parse(file);
  const int h = ref["height"], w = ref["width"];
  REQUIRE(ref["feature_channels"] == kC);
  // The contract input, channel c: 0.5 + 0.5 sin(0.7 c + 0.3 y + 0.2 x), split into the maps.
  auto input = [&](int first, int count) {
    const int sizes[] = {1, count, h, w};
    cv::Mat m(4, sizes, CV_32F);
    for (int c = 0; c < count; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int idx[] = {0, c, y, x};
          m.at<float>(idx) = 0.5f + 0.5f * std::sin(0.7f * (first + c) + 0.3f * y + 0.2f * x);
        }
    return m;
  };
  TemporalFlowModel model(dataFile("tff_tiny_c3.onnx"), kC);
  model.predict(input(0, kC), input(kC, 17));
  const cv::Mat tff = model.predict(input(kC + 17, kC), input(2 * kC + 17, 17));
  const auto& expected = ref["tff"];
  REQUIRE(tff.total() == expected.size());
  const float* got = tff.ptr<float>();
  for (size_t i = 0; i < expected.size(); ++i)
    CHECK(got[i] == Approx(expected[i].get<float>()).margin(1e-5));
}

TEST_CASE("TFF runner refuses models and maps that do not fit", "[tracking][tff_model]") {
  CHECK_THROWS_WITH(TemporalFlowModel(dataFile("absent.onnx"), kC),
                    Catch::Contains("absent.onnx") && Catch::Contains("does not exist"));
  // The tiny model takes 40 channels; a spatial model with 24 feature channels needs 82.
  CHECK_THROWS_WITH(TemporalFlowModel(dataFile("tff_wiring_c3.onnx"), 24),
                    Catch::Contains("takes 40") && Catch::Contains("needs 82"));
  CHECK_THROWS_WITH(TemporalFlowModel(dataFile("tff_bad_output_c3.onnx"), kC),
                    Catch::Contains("expected {1, 34"));
  CHECK_THROWS_WITH(TemporalFlowModel(dataFile("tff_tiny_c3_expected.json"), kC),
                    Catch::Contains("not an ONNX model"));
  if (cv::dnn::getAvailableTargets(cv::dnn::DNN_BACKEND_CUDA).empty()) {
    EngineOptions dnn;
    dnn.backend = DnnBackend::kCuda;
    dnn.target = DnnTarget::kCuda;
    CHECK_THROWS_WITH(TemporalFlowModel(dataFile("tff_wiring_c3.onnx"), kC, dnn),
                      Catch::Contains("not available in this OpenCV"));
  }

  TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC);
  CHECK_THROWS_WITH(model.predict(features(0, 4, 4), beliefs(0, 5, 4)),
                    Catch::Contains("belief map"));
  CHECK_THROWS_WITH(
      model.predict(blob(4, 4, 4, [](int, int, int) { return 0.f; }), beliefs(0, 4, 4)),
      Catch::Contains("{1, 3, H, W}"));
  CHECK_THROWS_AS(model.predict(cv::Mat(), cv::Mat()), Error);
}

TEST_CASE("TFF runner: resampled (max_grid_side) and moved by the camera, the field is exact",
          "[tracking][tff_model]") {
  // A 12 x 20 grid with max_grid_side 10 runs on 6 x 10 cells (half in each direction). Maps
  // linear in x and y stay linear through the area shrink, the bilinear warp and the bilinear
  // enlargement back, so wherever no step reads outside its grid the wiring model's odd channels
  // show the previous maps at the camera motion's source: previous(M^-1 p). A zoom makes the
  // network grid's offset count (cv::resize aligns pixel centres): with the offset left out, the
  // source moves by (zoom - 1) x 0.5 / 2 = 0.0625 network cells in x and y.
  constexpr int h = 12, w = 20, nh = 6, nw = 10;
  auto linear_features = [](int frame) -> cv::Mat {
    return blob(kC, h, w, [](int c, int y, int x) { return 0.1f * c + 0.5f * y + 0.25f * x; }) +
           cv::Scalar(frame);
  };
  auto linear_beliefs = [](int frame) -> cv::Mat {
    return blob(17, h, w, [](int c, int y, int x) { return 0.03f * c + 0.2f * y - 0.3f * x; }) +
           cv::Scalar(frame);
  };
  // What the wiring model's odd channel 2j+1 shows of frame 1 at a maps point (x, y).
  auto previous = [](int j, float y, float x) {
    const float f = 0.1f * (j % kC) + 0.5f * y + 0.25f * x + 1;
    const float b = 0.03f * j + 0.2f * y - 0.3f * x + 1;
    return b + 10 * f;
  };
  const float zoom = 1.25f;
  const cv::Matx23f camera(zoom, 0, 0.8f, 0, zoom, -0.6f);  // maps cells, previous -> current
  TemporalFlowModel model(dataFile("tff_wiring_c3.onnx"), kC, EngineOptions{}, 10);
  CHECK(model.predict(linear_features(1), linear_beliefs(1)).empty());
  const cv::Mat tff = model.predict(linear_features(2), linear_beliefs(2), camera);
  REQUIRE(tff.dims == 4);
  REQUIRE(tff.size[2] == h);
  REQUIRE(tff.size[3] == w);
  // Maps cell p reads network cells around q = (p - 0.5) / 2 (the enlargement); each of those
  // reads the previous network maps at the camera motion's source (the warp).
  auto source = [&](float qx, float qy) {  // network cell -> its source, network cells
    const float px = 2 * qx + 0.5f, py = 2 * qy + 0.5f;
    return cv::Point2f(((px - 0.8f) / zoom - 0.5f) / 2, ((py + 0.6f) / zoom - 0.5f) / 2);
  };
  int checked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float qx = (x - 0.5f) / 2, qy = (y - 0.5f) / 2;
      bool inside = qx >= 0 && qy >= 0 && qx <= nw - 1 && qy <= nh - 1;
      for (float cx : {std::floor(qx), std::ceil(qx)})
        for (float cy : {std::floor(qy), std::ceil(qy)}) {
          const cv::Point2f r = source(cx, cy);
          inside = inside && r.x >= 0 && r.y >= 0 && r.x <= nw - 1 && r.y <= nh - 1;
        }
      if (!inside) continue;
      ++checked;
      // warpAffine places its source on a 1/32-cell raster: at most 1/64 network cell off in x
      // and y, i.e. (|slope x| + |slope y|) / 64 per network cell; the slopes of `previous` are
      // 2.2 and 5.2 per maps cell, 4.4 and 10.4 per network cell: 0.23. The missing offset
      // would err by 0.0625 x (4.4 + 10.4) = 0.93.
      const float sx = (x - 0.8f) / zoom, sy = (y + 0.6f) / zoom;  // camera^-1 (x, y)
      for (int j = 0; j < 17; ++j)
        CHECK(at(tff, 2 * j + 1, y, x) == Approx(previous(j, sy, sx)).margin(0.3));
    }
  CHECK(checked >= 40);  // most of the interior
}
