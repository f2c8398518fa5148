// MatPool (core/engine/mat_pool.hpp): a buffer comes back only once nobody else holds it, and
// buffers of a shape no longer asked for are let go.
#include <catch2/catch.hpp>

#include "../../core/engine/mat_pool.hpp"

using jointflow::detail::MatPool;

TEST_CASE("MatPool reuses a buffer only once its holders have let go") {
  MatPool pool;
  const std::vector<int> shape{1, 3, 48, 64};
  cv::Mat a = pool.take(shape, CV_32F);
  REQUIRE(a.dims == 4);
  CHECK(a.size[2] == 48);
  CHECK(a.type() == CV_32F);
  CHECK(a.isContinuous());
  const uchar* first = a.data;

  cv::Mat held = a;  // a second holder (a tracker keeping the maps)
  a.release();
  cv::Mat b = pool.take(shape, CV_32F);
  CHECK(b.data != first);               // still held: never handed out again
  const cv::Mat roi = b.reshape(1, 1);  // another header over the same buffer holds it too
  b.release();

  held.release();
  cv::Mat c = pool.take(shape, CV_32F);
  CHECK(c.data == first);  // free again: reused
  cv::Mat d = pool.take(shape, CV_32F);
  CHECK(d.data != roi.data);  // still held through the header
  CHECK(pool.size() == 3);

  // Another type or shape is another buffer.
  CHECK(pool.take(shape, CV_8U).type() == CV_8U);
  CHECK(pool.take({1, 3, 24, 32}, CV_32F).size[2] == 24);
}

TEST_CASE("MatPool lets go of free buffers of a shape no longer asked for") {
  MatPool pool;
  cv::Mat kept = pool.take({1, 17, 120, 160}, CV_32F);
  pool.take({1, 17, 144, 192}, CV_32F);  // a resolution met once, then never again
  REQUIRE(pool.size() == 2);
  for (int i = 0; i < 100; ++i) pool.take({1, 17, 120, 160}, CV_32F);
  // The free 144x192 buffer is gone; the one still held stays, and one 120x160 is in use.
  CHECK(pool.size() == 2);
  kept.release();
}
