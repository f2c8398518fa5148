// Crossings and meetings of two walkers with the Bonn train people's articulation (crossings.hpp).
#include "crossings.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "assoc_sim.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/posetrack_joints.hpp"

namespace jointflow::bench {

namespace pt = jointflow::posetrack;

namespace {

// PoseTrack's videos run at about 25 frames/s: the articulation plays at its own speed.
constexpr double kTrainFps = 25.0;
// A train person's frames are used where they show at least this many COCO joints, an ankle and
// a shoulder (a whole body), and a person needs this many such frames in a row.
constexpr int kMinJoints = 10;
constexpr size_t kMinFrames = 16;

// One train person's articulation: per frame, each joint's offset from the keypoint box's centre
// in heights (the median keypoint box height of the person is 1), or NaN where not annotated.
struct Articulation {
  std::string source;
  std::vector<std::array<cv::Point2f, kNumJoints>> frames;
};

bool wholeBody(const Pose& p) {
  const auto seen = [&](int j) { return p.keypoints[j].score > 0.f; };
  return p.countVisible(1e-6f) >= kMinJoints && (seen(15) || seen(16)) && (seen(5) || seen(6));
}

// The longest run of whole-body frames of every person of every sequence.
std::vector<Articulation> readArticulations(const std::string& folder) {
  std::vector<Articulation> out;
  for (const std::string& file : pt::listSequenceFiles(folder)) {
    const pt::Sequence seq = pt::readSequence(file);
    std::map<std::int64_t, std::vector<std::vector<Pose>>> runs;  // id -> runs of poses
    std::map<std::int64_t, size_t> last_frame;
    for (size_t f = 0; f < seq.frames.size(); ++f)
      for (const pt::Person& person : seq.frames[f].people) {
        if (!person.track_id) continue;
        const Pose p = cocoPose(person.joints, 1.f);
        if (!wholeBody(p)) continue;
        auto& r = runs[*person.track_id];
        auto it = last_frame.find(*person.track_id);
        if (r.empty() || it == last_frame.end() || it->second + 1 != f) r.emplace_back();
        r.back().push_back(p);
        last_frame[*person.track_id] = f;
      }
    for (const auto& [id, person_runs] : runs) {
      const auto longest =
          std::max_element(person_runs.begin(), person_runs.end(),
                           [](const auto& a, const auto& b) { return a.size() < b.size(); });
      if (longest->size() < kMinFrames) continue;
      std::vector<float> heights;
      for (const Pose& p : *longest) heights.push_back(p.box.h);
      std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
      const float h = std::max(heights[heights.size() / 2], 1.f);
      Articulation a;
      a.source = seq.name + "#" + std::to_string(id);
      for (const Pose& p : *longest) {
        const cv::Point2f c(p.box.x + 0.5f * p.box.w, p.box.y + 0.5f * p.box.h);
        std::array<cv::Point2f, kNumJoints> offsets;
        for (int j = 0; j < kNumJoints; ++j)
          offsets[j] = p.keypoints[j].score > 0.f
                           ? (cv::Point2f(p.keypoints[j].x, p.keypoints[j].y) - c) / h
                           : cv::Point2f(NAN, NAN);
        a.frames.push_back(offsets);
      }
      out.push_back(std::move(a));
    }
  }
  return out;
}

// The articulation at `seconds`, played forward and back (ping-pong) to last any case.
const std::array<cv::Point2f, kNumJoints>& articulationAt(const Articulation& a, double seconds) {
  const int n = static_cast<int>(a.frames.size());
  const int period = 2 * n - 2;
  int k = static_cast<int>(std::lround(seconds * kTrainFps)) % period;
  if (k >= n) k = period - k;
  return a.frames[k];
}

// Where a walker's centre is at `t`: coming from `side` (-1 left, +1 right) towards `meet`, then
// on past it ("cross") or, after `linger` s standing `stand` px short of it, back ("meet").
cv::Point2f walkerAt(CrossingKind kind, double t, float side, cv::Point2f meet, float v,
                     const CrossingOptions& o, float stand) {
  const double arrive = o.approach;
  if (kind == CrossingKind::kCross)
    return {meet.x + side * v * static_cast<float>(arrive - t), meet.y};
  const float stop = meet.x + side * stand;
  const double walked = t < arrive ? arrive - t : std::max(0.0, t - arrive - o.linger);
  return {stop + side * v * static_cast<float>(walked), meet.y};
}

Pose placed(const std::array<cv::Point2f, kNumJoints>& offsets, cv::Point2f centre, float height) {
  Pose p;
  for (int j = 0; j < kNumJoints; ++j)
    if (std::isfinite(offsets[j].x))
      p.keypoints[j] = {centre.x + height * offsets[j].x, centre.y + height * offsets[j].y, 1.f};
  p.box = p.keypointBox(0.f);
  return p;
}

// What a detector reports of `truth`: joints covered by `front` (grown by the margin) left out,
// others missed at random, the rest jittered; empty when too few remain.
std::optional<Pose> detect(const Pose& truth, const Pose* front, const CrossingOptions& o,
                           std::mt19937& rng) {
  std::normal_distribution<float> gauss(0.f, o.jitter * o.height);
  std::uniform_real_distribution<float> uniform(0.f, 1.f);
  Box cover;
  if (front) {
    const float m = o.cover_margin * o.height;
    cover = {front->box.x - m, front->box.y - m, front->box.w + 2 * m, front->box.h + 2 * m};
  }
  Pose p;
  int seen = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const Keypoint& k = truth.keypoints[j];
    if (k.score <= 0.f) continue;
    const bool covered = front && k.x >= cover.x && k.x <= cover.x + cover.w && k.y >= cover.y &&
                         k.y <= cover.y + cover.h;
    if (covered || uniform(rng) < o.miss_joint) continue;
    p.keypoints[j] = {k.x + gauss(rng), k.y + gauss(rng), 0.5f + 0.5f * uniform(rng)};
    ++seen;
  }
  if (seen < o.min_visible) return std::nullopt;
  p.score = 0.3f + 0.6f * static_cast<float>(seen) / kNumJoints;
  p.box = p.keypointBox(0.f);
  return p;
}

}  // namespace

std::vector<CrossingCase> makeCrossings(const std::string& train_folder, int pairs,
                                        const std::vector<float>& offsets, const CrossingOptions& o,
                                        unsigned seed) {
  const std::vector<Articulation> people = readArticulations(train_folder);
  std::vector<CrossingCase> cases;
  if (people.size() < 2) return cases;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, people.size() - 1);
  const float v = o.speed * o.height;
  const cv::Point2f meet(480.f, 270.f);
  const int frames = static_cast<int>(std::lround((2.0 * o.approach + o.linger) * o.fps));
  for (int pair = 0; pair < pairs; ++pair) {
    const Articulation& a = people[pick(rng)];
    const Articulation* b = &people[pick(rng)];
    while (b->source == a.source) b = &people[pick(rng)];
    // Each case starts the two articulations at their own random phase.
    const double phase_a = std::uniform_real_distribution<double>(0.0, 2.0)(rng);
    const double phase_b = std::uniform_real_distribution<double>(0.0, 2.0)(rng);
    for (const CrossingKind kind : {CrossingKind::kCross, CrossingKind::kMeet})
      for (const float offset : offsets) {
        CrossingCase c;
        c.kind = kind;
        c.offset = offset;
        c.source = a.source + "+" + b->source;
        c.meet_frame = static_cast<int>(std::lround(o.approach * o.fps));
        c.fps = o.fps;
        const int n = kind == CrossingKind::kCross
                          ? static_cast<int>(std::lround(2.0 * o.approach * o.fps))
                          : frames;
        // People who meet stand a third of a height apart.
        const float stand = 0.17f * o.height;
        for (int k = 0; k <= n; ++k) {
          const double t = k / o.fps;
          // 0 comes from the left on the upper line, 1 from the right on the lower line (in
          // front).
          const Pose back = placed(articulationAt(a, t + phase_a),
                                   walkerAt(kind, t, -1.f, meet, v, o, stand), o.height);
          const Pose front = placed(
              articulationAt(*b, t + phase_b),
              walkerAt(kind, t, 1.f, meet + cv::Point2f(0.f, offset * o.height), v, o, stand),
              o.height);
          std::vector<std::pair<int, Pose>> seen;
          if (auto d = detect(back, &front, o, rng)) seen.emplace_back(0, *d);
          if (auto d = detect(front, nullptr, o, rng)) seen.emplace_back(1, *d);
          std::shuffle(seen.begin(), seen.end(), rng);
          c.frames.push_back(std::move(seen));
        }
        cases.push_back(std::move(c));
      }
  }
  return cases;
}

CrossingOutcome trackCrossings(const std::vector<CrossingCase>& cases,
                               const TrackerSettings& settings, std::vector<std::string>* failures,
                               std::ostream* trace) {
  CrossingOutcome out;
  for (const CrossingCase& c : cases) {
    PoseAssociator associator(settings);
    // The id each person was last reported under, and the one they came with (before the two
    // came within a height of each other).
    std::map<int, std::int64_t> last, came_with, left_with;
    const int settle = c.meet_frame / 2;
    int switches = 0;
    for (size_t k = 0; k < c.frames.size(); ++k) {
      AssociationFrame in;
      for (const auto& [identity, pose] : c.frames[k]) in.poses.push_back(pose);
      in.time = static_cast<double>(k) / c.fps;
      left_with.clear();
      for (const TrackedPose& tp : associator.update(in)) {
        const int who = c.frames[k][tp.detection].first;
        auto [it, first] = last.emplace(who, tp.track_id);
        if (!first && it->second != tp.track_id) ++switches;
        it->second = tp.track_id;
        if (static_cast<int>(k) <= settle) came_with[who] = tp.track_id;
        left_with[who] = tp.track_id;
      }
      if (trace) {
        *trace << c.source << " frame " << k << ":";
        for (const auto& [who, pose] : c.frames[k])
          *trace << "  person " << who << " at (" << static_cast<int>(pose.box.x + pose.box.w / 2)
                 << ", " << static_cast<int>(pose.box.y + pose.box.h / 2) << ") "
                 << pose.countVisible(1e-6f) << " joints"
                 << (left_with.count(who) ? " id " + std::to_string(left_with[who]) : " no id");
        *trace << "\n";
      }
    }
    ++out.cases;
    out.switches += switches;
    const bool both_left = left_with.size() == 2, both_came = came_with.size() == 2;
    bool swapped = false, fresh = false;
    for (const auto& [who, id] : left_with) {
      const auto other = came_with.find(1 - who), own = came_with.find(who);
      if (other != came_with.end() && other->second == id) swapped = true;
      if (own == came_with.end() || own->second != id) fresh = true;
    }
    const char* verdict = nullptr;
    if (!both_left || !both_came) {
      ++out.lost;
      verdict = "lost";
    } else if (swapped) {
      ++out.swapped;
      verdict = "swapped";
    } else if (fresh) {
      ++out.new_id;
      verdict = "new id";
    } else {
      ++out.kept;
    }
    if (verdict && failures)
      failures->push_back(std::string(c.kind == CrossingKind::kCross ? "cross" : "meet") +
                          " offset " + std::to_string(c.offset) + " " + c.source + ": " + verdict +
                          ", " + std::to_string(switches) + " switches");
  }
  return out;
}

}  // namespace jointflow::bench
