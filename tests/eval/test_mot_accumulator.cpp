// MotAccumulator against hand-counted CLEAR MOT events (py-motmetrics 1.4.0 semantics).
#include <cmath>

#include <catch2/catch.hpp>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"

using jointflow::MotAccumulator;

namespace {
const double kNo = std::nan("");  // this pair cannot match
}

TEST_CASE("perfect tracking: only matches", "[eval][mot]") {
  MotAccumulator acc;
  for (int f = 0; f < 3; ++f) acc.update({1, 2}, {7, 8}, {0.1, kNo, kNo, 0.2});
  const auto& c = acc.counts();
  CHECK(c.objects == 6);
  CHECK(c.matches == 6);
  CHECK(c.switches + c.misses + c.false_positives == 0);
  CHECK(c.matched_distance == Approx(0.9));
  CHECK(c.frames == 3);
}

TEST_CASE("swapped hypotheses are two identity switches", "[eval][mot]") {
  MotAccumulator acc;
  acc.update({1, 2}, {7, 8}, {0.1, kNo, kNo, 0.1});
  acc.update({1, 2}, {7, 8}, {kNo, 0.1, 0.1, kNo});
  CHECK(acc.counts().switches == 2);
  CHECK(acc.counts().matches == 2);
  // Staying with the new hypotheses is no further switch.
  acc.update({1, 2}, {7, 8}, {kNo, 0.1, 0.1, kNo});
  CHECK(acc.counts().switches == 2);
  CHECK(acc.counts().matches == 4);
}

TEST_CASE("a previous pair that can still match is kept, even when another is closer",
          "[eval][mot]") {
  MotAccumulator acc;
  acc.update({1}, {7}, {0.1});
  acc.update({1}, {7, 8}, {0.4, 0.05});
  const auto& c = acc.counts();
  CHECK(c.matches == 2);
  CHECK(c.switches == 0);
  CHECK(c.false_positives == 1);
  CHECK(c.matched_distance == Approx(0.5));
}

TEST_CASE("unmatched objects are misses, unmatched hypotheses false positives", "[eval][mot]") {
  MotAccumulator acc;
  acc.update({1, 2, 3}, {7}, {kNo, kNo, kNo});
  acc.update({}, {7, 8}, {});
  acc.update({1}, {}, {});
  const auto& c = acc.counts();
  CHECK(c.objects == 4);
  CHECK(c.misses == 4);
  CHECK(c.false_positives == 3);
  CHECK(c.detections() == 0);
}

TEST_CASE("the assignment makes the most pairs before it minimises distance", "[eval][mot]") {
  // Greedy would pair 1-7 (0.1) and leave 2 alone; motmetrics pairs 1-8 and 2-7.
  MotAccumulator acc;
  acc.update({1, 2}, {7, 8}, {0.1, 0.2, 0.15, kNo});
  const auto& c = acc.counts();
  CHECK(c.matches == 2);
  CHECK(c.misses == 0);
  CHECK(c.matched_distance == Approx(0.35));
}

TEST_CASE("events distance sums every pair within reach, as motmetrics' events['D']",
          "[eval][mot]") {
  MotAccumulator acc;
  acc.update({1}, {7, 8}, {0.1, 0.3});  // RAW 0.1 + 0.3, MATCH 0.1
  CHECK(acc.counts().matched_distance == Approx(0.1));
  CHECK(acc.counts().events_distance == Approx(0.5));
  // A hypothesis taken over by a new object: TRANSFER and MIGRATE repeat the distance.
  MotAccumulator transfer;
  transfer.update({1}, {7}, {0.2});
  transfer.update({2}, {7}, {0.2});
  CHECK(transfer.counts().switches == 0);
  CHECK(transfer.counts().events_distance == Approx(0.2 * 2 + 0.2 * 4));
}

TEST_CASE("malformed updates are refused", "[eval][mot]") {
  MotAccumulator acc;
  CHECK_THROWS_AS(acc.update({1, 2}, {7}, {0.1}), jointflow::Error);
  CHECK_THROWS_AS(acc.update({1, 1}, {7}, {0.1, 0.1}), jointflow::Error);
}
