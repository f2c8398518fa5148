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

// Identity measures (IDTP / IDFP / IDFN), counted by hand: one global pairing of object ids with
// hypothesis ids for the whole sequence, covering the most frames in reach.

TEST_CASE("IDF1: ids swapped half way keep half the frames", "[eval][mot][idf1]") {
  MotAccumulator acc;
  for (int f = 0; f < 2; ++f) acc.update({1, 2}, {7, 8}, {0.1, kNo, kNo, 0.1});  // 1-7, 2-8
  for (int f = 0; f < 2; ++f) acc.update({1, 2}, {7, 8}, {kNo, 0.1, 0.1, kNo});  // 1-8, 2-7
  const auto c = acc.counts();
  CHECK(c.switches == 2);
  // Pairing 1-7, 2-8 (or 1-8, 2-7) covers 2 + 2 of the 8 appearances on each side.
  CHECK(c.id_true_positives == 4);
  CHECK(c.id_false_negatives == 4);
  CHECK(c.id_false_positives == 4);
}

TEST_CASE("IDF1: a fragmented track counts its longer piece", "[eval][mot][idf1]") {
  MotAccumulator acc;
  for (int f = 0; f < 4; ++f) acc.update({1}, {7}, {0.1});
  for (int f = 0; f < 2; ++f) acc.update({1}, {8}, {0.1});
  const auto c = acc.counts();
  CHECK(c.switches == 1);
  CHECK(c.id_true_positives == 4);   // 1 -> 7
  CHECK(c.id_false_negatives == 2);  // the frames under 8
  CHECK(c.id_false_positives == 2);  // 8's frames, paired with no object
  CHECK(c.predictions() == 6);
}

TEST_CASE("IDF1: the pairing is global, not greedy, and counts every pair within reach",
          "[eval][mot][idf1]") {
  MotAccumulator acc;
  // Object 1 is in reach of 7 in 5 frames and of 8 in 4 of them (the frame's MOTA match is 7);
  // object 2 is in reach of 7 in 4 later frames. Greedy 1-7 covers 5; 1-8 + 2-7 covers 8.
  for (int f = 0; f < 4; ++f) acc.update({1}, {7, 8}, {0.1, 0.2});
  acc.update({1}, {7}, {0.1});
  for (int f = 0; f < 4; ++f) acc.update({2}, {7}, {0.1});
  const auto c = acc.counts();
  CHECK(c.matches == 9);
  CHECK(c.false_positives == 4);  // 8, never the MOTA match
  CHECK(c.id_true_positives == 8);
  CHECK(c.id_false_negatives == 9 - 8);
  CHECK(c.id_false_positives == 13 - 8);
}

TEST_CASE("IDF1: pairs out of reach and empty frames cover nothing", "[eval][mot][idf1]") {
  MotAccumulator acc;
  CHECK(acc.counts().id_true_positives == 0);
  acc.update({1}, {7}, {kNo});
  acc.update({}, {7}, {});
  acc.update({1}, {}, {});
  const auto c = acc.counts();
  CHECK(c.id_true_positives == 0);
  CHECK(c.id_false_negatives == 2);
  CHECK(c.id_false_positives == 2);
}

TEST_CASE("IDF1: a tracker making a new id every frame is solved exactly", "[eval][mot][idf1]") {
  // 3 people, 400 frames, a fresh hypothesis id for each person in each frame except person 1,
  // who keeps id 0 in every 4th frame: the only pairing worth more than one frame.
  MotAccumulator acc;
  std::int64_t next = 1;
  for (int f = 0; f < 400; ++f) {
    const std::int64_t first = f % 4 == 0 ? 0 : next++;
    acc.update({1, 2, 3}, {first, next, next + 1}, {0.1, kNo, kNo, kNo, 0.1, kNo, kNo, kNo, 0.1});
    next += 2;
  }
  const auto c = acc.counts();
  CHECK(c.id_true_positives == 100 + 1 + 1);
  CHECK(c.id_false_negatives == 1200 - 102);
}
