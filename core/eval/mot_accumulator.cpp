// py-motmetrics 1.4.0 MOTAccumulator.update, event for event (CLEAR MOT, Bernardin &
// Stiefelhagen 2008), keeping counts instead of an event table.
#include <cmath>
#include <set>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "linear_assignment.hpp"

namespace jointflow {

MotAccumulator::Counts& MotAccumulator::Counts::operator+=(const Counts& o) {
  objects += o.objects;
  matches += o.matches;
  switches += o.switches;
  misses += o.misses;
  false_positives += o.false_positives;
  frames += o.frames;
  id_true_positives += o.id_true_positives;
  id_false_positives += o.id_false_positives;
  id_false_negatives += o.id_false_negatives;
  matched_distance += o.matched_distance;
  events_distance += o.events_distance;
  return *this;
}

namespace {

void requireUnique(const std::vector<std::int64_t>& ids, const char* what) {
  if (std::set<std::int64_t>(ids.begin(), ids.end()).size() != ids.size()) {
    throw Error(std::string("MotAccumulator::update: repeated ") + what + " id in one frame");
  }
}

}  // namespace

void MotAccumulator::update(const std::vector<std::int64_t>& object_ids,
                            const std::vector<std::int64_t>& hypothesis_ids,
                            const std::vector<double>& distances) {
  const int n = static_cast<int>(object_ids.size());
  const int m = static_cast<int>(hypothesis_ids.size());
  if (distances.size() != static_cast<std::size_t>(n) * m) {
    throw Error("MotAccumulator::update: " + std::to_string(distances.size()) + " distances for " +
                std::to_string(n) + " objects x " + std::to_string(m) + " hypotheses");
  }
  requireUnique(object_ids, "object");
  requireUnique(hypothesis_ids, "hypothesis");
  const std::int64_t frame = frame_++;
  ++counts_.frames;
  counts_.objects += n;

  // motmetrics records every finite distance as a RAW event; its events['D'] sums them too, and
  // its identity measures count them per pair.
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double d = distances[static_cast<std::size_t>(i) * m + j];
      if (!std::isfinite(d)) continue;
      counts_.events_distance += d;
      ++pair_frames_[{object_ids[i], hypothesis_ids[j]}];
    }
  }

  std::vector<char> object_done(n, 0), hypothesis_done(m, 0);
  auto record = [&](double d, bool is_switch) {
    (is_switch ? counts_.switches : counts_.matches) += 1;
    counts_.matched_distance += d;
    counts_.events_distance += d;
  };

  if (n > 0 && m > 0) {
    // 1. Carry forward last pairs that can still match.
    for (int i = 0; i < n; ++i) {
      auto prev = match_of_object_.find(object_ids[i]);
      if (prev == match_of_object_.end()) continue;
      int j = 0;
      while (j < m && (hypothesis_done[j] || hypothesis_ids[j] != prev->second)) ++j;
      if (j == m) continue;
      const double d = distances[i * m + j];
      if (!std::isfinite(d)) continue;
      object_done[i] = hypothesis_done[j] = 1;
      last_match_[object_ids[i]] = frame;
      hypothesis_history_[hypothesis_ids[j]] = frame;
      record(d, false);
    }

    // 2. Pair the rest optimally; a pair that contradicts the object's last one is a switch.
    std::vector<double> rest(distances);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        if (object_done[i] || hypothesis_done[j]) rest[i * m + j] = std::nan("");
      }
    }
    const std::vector<int> col = eval::motAssignment(rest, n, m);
    for (int i = 0; i < n; ++i) {
      const int j = col[i];
      if (j < 0) continue;
      const double d = rest[i * m + j];
      const std::int64_t o = object_ids[i], h = hypothesis_ids[j];
      auto prev = match_of_object_.find(o);
      const bool is_switch = prev != match_of_object_.end() && prev->second != h;
      // motmetrics adds ASCEND / TRANSFER / MIGRATE events carrying the same distance.
      if (is_switch && !hypothesis_history_.count(h)) counts_.events_distance += d;  // ASCEND
      auto owner = object_of_hypothesis_.find(h);
      if (owner != object_of_hypothesis_.end() && owner->second != o) {  // TRANSFER
        if (!last_match_.count(o)) counts_.events_distance += d;         // MIGRATE
        counts_.events_distance += d;
      }
      hypothesis_history_[h] = frame;
      last_match_[o] = frame;
      record(d, is_switch);
      object_done[i] = hypothesis_done[j] = 1;
      match_of_object_[o] = h;
      object_of_hypothesis_[h] = o;
    }
  }

  // 3. and 4. Whatever is left is missed or false.
  for (int i = 0; i < n; ++i) counts_.misses += object_done[i] ? 0 : 1;
  for (int j = 0; j < m; ++j) counts_.false_positives += hypothesis_done[j] ? 0 : 1;
}

MotAccumulator::Counts MotAccumulator::counts() const {
  Counts c = counts_;
  c.id_true_positives = eval::identityTruePositives(pair_frames_);
  c.id_false_negatives = c.objects - c.id_true_positives;
  c.id_false_positives = c.predictions() - c.id_true_positives;
  return c;
}

}  // namespace jointflow
