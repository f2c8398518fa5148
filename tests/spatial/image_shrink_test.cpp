// shrinkImage and shrinkToSide: the letterbox's, the camera estimate's and the flow's shrink, fast
// and without aliasing.
#include <catch2/catch.hpp>

#include <opencv2/imgproc.hpp>

#include "jointflow/image_shrink.hpp"

using namespace jointflow;

namespace {

/// A textured image: noise smoothed to features of a few pixels, like a frame's detail.
cv::Mat texture(cv::Size size, int type) {
  cv::Mat noise(size, type);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  return noise;
}

double meanAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  return cv::mean(d.reshape(1))[0];
}

}  // namespace

TEST_CASE("A shrink by a fractional factor does not alias fine stripes") {
  // One-pixel stripes average to grey; a bilinear shrink by 2.4x samples them unevenly and
  // prints bands (what INTER_LINEAR alone gives, checked below).
  cv::Mat stripes(540, 960, CV_8UC1);
  for (int c = 0; c < stripes.cols; ++c) stripes.col(c).setTo(c % 2 ? 255 : 0);
  const cv::Mat small = shrinkImage(stripes, cv::Size(400, 225));
  REQUIRE(small.size() == cv::Size(400, 225));
  cv::Scalar mean, stddev;
  cv::meanStdDev(small, mean, stddev);
  CHECK(mean[0] == Approx(127.5).margin(1.0));
  CHECK(stddev[0] < 2.0);

  cv::Mat bilinear;
  cv::resize(stripes, bilinear, cv::Size(400, 225), 0, 0, cv::INTER_LINEAR);
  cv::meanStdDev(bilinear, mean, stddev);
  CHECK(stddev[0] > 30.0);
}

TEST_CASE("A shrink gives nearly what an area resize gives, at any size") {
  struct Case {
    cv::Size from, to;
    int type;
  };
  const Case cases[] = {
      {{768, 576}, {640, 480}, CV_8UC3},  // vtest.avi at max:640
      {{768, 576}, {400, 300}, CV_8UC1},  // the camera estimate's search image
      {{1920, 1080}, {640, 360}, CV_8UC3},
      {{1280, 720}, {640, 360}, CV_8UC3},  // exactly half: the area resize itself
      {{1001, 751}, {333, 250}, CV_8UC1},  // odd sides
  };
  for (const Case& c : cases) {
    CAPTURE(c.from, c.to);
    const cv::Mat image = texture(c.from, c.type);
    const cv::Mat small = shrinkImage(image, c.to);
    REQUIRE(small.size() == c.to);
    REQUIRE(small.type() == c.type);
    cv::Mat area;
    cv::resize(image, area, c.to, 0, 0, cv::INTER_AREA);
    CHECK(meanAbsDifference(small, area) < 2.0);
  }
  const cv::Mat image = texture({1280, 720}, CV_8UC3);
  cv::Mat area;
  cv::resize(image, area, {640, 360}, 0, 0, cv::INTER_AREA);
  CHECK(meanAbsDifference(shrinkImage(image, {640, 360}), area) == 0.0);
}

TEST_CASE("An image of the target size is returned as it is; a larger target is bilinear") {
  const cv::Mat image = texture({320, 240}, CV_8UC3);
  CHECK(shrinkImage(image, image.size()).data == image.data);
  cv::Mat bilinear;
  cv::resize(image, bilinear, {400, 300}, 0, 0, cv::INTER_LINEAR);
  CHECK(meanAbsDifference(shrinkImage(image, {400, 300}), bilinear) == 0.0);
}

TEST_CASE("shrinkToSide brings the longer side to at most the given one, aspect kept") {
  const cv::Mat grey = texture({960, 540}, CV_8UC1);
  const cv::Mat half = shrinkToSide(grey, 480);
  CHECK(half.size() == cv::Size(480, 270));
  CHECK(meanAbsDifference(half, shrinkImage(grey, {480, 270})) == 0.0);
  CHECK(shrinkToSide(texture({768, 576}, CV_8UC1), 400).size() == cv::Size(400, 300));
  CHECK(shrinkToSide(texture({540, 960}, CV_8UC1), 400).size() == cv::Size(225, 400));
  CHECK(shrinkToSide(texture({2000, 2}, CV_8UC1), 400).size() == cv::Size(400, 1));
  // No larger: a copy of its own, the same pixels.
  const cv::Mat small = texture({320, 240}, CV_8UC1);
  const cv::Mat kept = shrinkToSide(small, 480);
  CHECK(kept.data != small.data);
  CHECK(meanAbsDifference(kept, small) == 0.0);
}
