// Frame <-> network input <-> output grid mapping, single- and multi-scale, to sub-pixel accuracy.
#include <catch2/catch.hpp>

#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "jointflow/grid_resample.hpp"
#include "jointflow/letterbox.hpp"

using namespace jointflow;

namespace {

// A smooth bright blob centred at a sub-pixel position, so that its centroid is its centre.
cv::Mat blobImage(cv::Size size, cv::Point2f centre, float sigma) {
  cv::Mat img(size, CV_8UC3);
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      const float d2 = (c - centre.x) * (c - centre.x) + (r - centre.y) * (r - centre.y);
      const auto v = cv::saturate_cast<uchar>(250.f * std::exp(-d2 / (2 * sigma * sigma)));
      img.at<cv::Vec3b>(r, c) = {v, v, v};
    }
  }
  return img;
}

cv::Point2f centroid(const cv::Mat& img) {
  cv::Mat gray;
  cv::extractChannel(img, gray, 0);
  const cv::Moments m = cv::moments(gray);
  return {static_cast<float>(m.m10 / m.m00), static_cast<float>(m.m01 / m.m00)};
}

InputSize policy(const std::string& s) {
  return InputSize::parse(s);
}

}  // namespace

TEST_CASE("Size rules give the models' accepted input sizes") {
  CHECK(SizeRule{32, 0}.validAtLeast(576) == 576);
  CHECK(SizeRule{32, 0}.validAtLeast(577) == 608);
  CHECK(SizeRule{32, 0}.validAtLeast(1) == 32);
  CHECK(SizeRule{16, 1}.validAtLeast(768) == 769);
  CHECK(SizeRule{16, 1}.validAtLeast(769) == 769);
  CHECK(SizeRule{16, 1}.validAtLeast(770) == 785);
}

TEST_CASE("Input size policies") {
  const SizeRule movenet{32, 0};
  SECTION("native pads at the right and bottom only") {
    const Letterbox b = computeLetterbox({768, 576}, policy("native"), 1.f, movenet);
    CHECK(b.input == cv::Size(768, 576));
    CHECK(b.content == cv::Rect(0, 0, 768, 576));
    const Letterbox odd = computeLetterbox({961, 541}, policy("native"), 1.f, movenet);
    CHECK(odd.input == cv::Size(992, 544));
  }
  SECTION("max side shrinks, never enlarges") {
    const Letterbox b = computeLetterbox({960, 540}, policy("max:640"), 1.f, movenet);
    CHECK(b.content == cv::Rect(0, 0, 640, 360));
    CHECK(b.input == cv::Size(640, 384));
    CHECK(computeLetterbox({320, 240}, policy("max:640"), 1.f, movenet).content.size() ==
          cv::Size(320, 240));
  }
  SECTION("fixed letterboxes into the centre") {
    const Letterbox b = computeLetterbox({960, 540}, policy("256x256"), 1.f, movenet);
    CHECK(b.input == cv::Size(256, 256));
    CHECK(b.content == cv::Rect(0, 56, 256, 144));
  }
  SECTION("scales multiply the policy's resize factor") {
    const Letterbox b = computeLetterbox({960, 540}, policy("max:640"), 0.5f, movenet);
    CHECK(b.content.size() == cv::Size(320, 180));
    CHECK(b.input == cv::Size(320, 192));
  }
  SECTION("bad policies and frames are errors") {
    REQUIRE_THROWS_WITH(InputSize::parse("big"), Catch::Contains("\"big\" is not one of"));
    REQUIRE_THROWS_WITH(computeLetterbox({1, 1}, policy("native"), 1.f, movenet),
                        Catch::Contains("1x1 pixels is too small"));
    REQUIRE_THROWS_WITH(computeLetterbox({64, 64}, policy("native"), 0.f, movenet),
                        Catch::Contains("scale must be a positive number"));
  }
  CHECK(policy("native").toString() == "native");
  CHECK(policy("320x240").toString() == "320x240");
  CHECK(policy("max:512").toString() == "max:512");
}

TEST_CASE("A point of the frame lands where the letterbox says, to sub-pixel accuracy") {
  const cv::Point2f centre(300.37f, 170.81f);
  const cv::Mat frame = blobImage({960, 540}, centre, 12.f);
  for (const std::string p : {"256x256", "max:640", "native", "400x300"}) {
    for (const SizeRule rule : {SizeRule{32, 0}, SizeRule{16, 1}}) {
      INFO(p << " rule " << rule.multiple << "k+" << rule.plus);
      const Letterbox box = computeLetterbox(frame.size(), policy(p), 1.f, rule);
      const cv::Mat input = applyLetterbox(frame, box);
      REQUIRE(input.size() == box.input);
      const cv::Point2f expected = box.frameToInput(centre);
      const cv::Point2f seen = centroid(input);
      CHECK(seen.x == Approx(expected.x).margin(0.05));
      CHECK(seen.y == Approx(expected.y).margin(0.05));
      // And back: the inverse maps and the grid transform agree.
      const cv::Point2f back = box.inputToFrame(seen);
      CHECK(back.x == Approx(centre.x).margin(0.05 * 960 / box.content.width));
      CHECK(back.y == Approx(centre.y).margin(0.05 * 540 / box.content.height));
      const GridTransform g = box.gridToFrame(4.f);
      const cv::Point2f via_grid = g.toFrame({expected.x / 4.f, expected.y / 4.f});
      CHECK(via_grid.x == Approx(centre.x).margin(1e-3));
      CHECK(via_grid.y == Approx(centre.y).margin(1e-3));
      const cv::Point2f grid = g.toGrid(centre);
      CHECK(grid.x == Approx(expected.x / 4.f).margin(1e-4));
    }
  }
}

TEST_CASE("Maps of several scales meet on one grid: peaks and displacement fields agree") {
  const cv::Size frame(960, 540);
  const SizeRule rule{32, 0};
  const InputSize p = policy("max:640");
  const Letterbox ref_box = computeLetterbox(frame, p, 1.f, rule);
  const GridTransform ref = ref_box.gridToFrame(4.f);
  const cv::Size ref_grid(ref_box.input.width / 4, ref_box.input.height / 4);
  const cv::Point2f target(411.3f, 203.9f);        // a joint, frame pixels
  const cv::Point2f displacement(-37.5f, 21.25f);  // a vector, frame pixels
  for (float scale : {0.5f, 1.5f, 2.f}) {
    INFO("scale " << scale);
    const Letterbox box = computeLetterbox(frame, p, scale, rule);
    const GridTransform g = box.gridToFrame(4.f);
    const cv::Size grid(box.input.width / 4, box.input.height / 4);
    // Channel 0: a wide Gaussian around the joint; channels 1, 2: the vector (x, y) in this
    // grid's cells; channel 3 the same vector, to stay unscaled (like a PAF).
    cv::Mat t(std::vector<int>{1, 4, grid.height, grid.width}, CV_32F);
    const cv::Point2f c = g.toGrid(target);
    const float sigma = 3.f * scale;
    for (int r = 0; r < grid.height; ++r) {
      for (int col = 0; col < grid.width; ++col) {
        const float d2 = (col - c.x) * (col - c.x) + (r - c.y) * (r - c.y);
        t.ptr<float>(0, 0)[r * grid.width + col] = std::exp(-d2 / (2 * sigma * sigma));
        t.ptr<float>(0, 1)[r * grid.width + col] = displacement.x / g.scale_x;
        t.ptr<float>(0, 2)[r * grid.width + col] = displacement.y / g.scale_y;
        t.ptr<float>(0, 3)[r * grid.width + col] = 0.6f;
      }
    }
    const cv::Mat out = resampleToGrid(t, g, ref, ref_grid, {{1, 2}});
    REQUIRE(out.size[2] == ref_grid.height);
    REQUIRE(out.size[3] == ref_grid.width);
    cv::Mat m(ref_grid, CV_32F, const_cast<float*>(out.ptr<float>(0, 0)));
    const cv::Moments mo = cv::moments(m);
    const cv::Point2f peak_frame =
        ref.toFrame({static_cast<float>(mo.m10 / mo.m00), static_cast<float>(mo.m01 / mo.m00)});
    CHECK(peak_frame.x == Approx(target.x).margin(0.5));
    CHECK(peak_frame.y == Approx(target.y).margin(0.5));
    const int r = ref_grid.height / 2, col = ref_grid.width / 2;
    CHECK(out.ptr<float>(0, 1)[r * ref_grid.width + col] * ref.scale_x ==
          Approx(displacement.x).margin(1e-3));
    CHECK(out.ptr<float>(0, 2)[r * ref_grid.width + col] * ref.scale_y ==
          Approx(displacement.y).margin(1e-3));
    CHECK(out.ptr<float>(0, 3)[r * ref_grid.width + col] == Approx(0.6f));
  }
}
