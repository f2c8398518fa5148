// reid-bench: how well each appearance model of re-identification (TrackerSettings::reid) tells
// people apart on real frames, and which reid_min_similarity and reentry_min_similarity that
// supports. vtest.avi's 795 frames go through the tracker's spatial model (its default settings);
// each pose is given the identity of the hand-made label box it overlaps (IoU >= 0.5, greedy by
// IoU, one to one: tests/data/vtest-identity), poses with no label are left out. The labels, not
// a tracker, say who is who, so no measurement depends on what it measures.
//
// A visit's appearance is kept as the tracker keeps a track's (pose_associator.cpp): the first
// descriptor, then blendAppearance(..., 0.9) with each pose that overlaps no other labelled pose
// by more than 10 % of its box. It is compared with:
//   - within a visit (reid_min_similarity's use, a lost track against a pose): the poses of frame
//     t + gap; rank-1 is the share where the visit's own pose beats every other person's;
//   - re-entry (reentry_min_similarity's use, reentry.cpp): a visit's appearance after its first
//     min_track_length poses (when the tracker decides) against the departed, i.e. each visit that
//     ended at most reentry_time before it started, at the end of that visit, last seen within
//     0.4 of the view's longer side of where the new visit starts (the tracker's reach).
// Writes docs/reid-bench.md.
//
//   build/bench/reid-bench [--video FILE] [--labels DIR] [--backend NAME] [--out FILE]
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/appearance.hpp"
#include "jointflow/mot_evaluation.hpp"
#include "jointflow/tracker.hpp"

using namespace jointflow;

namespace {

// Copies of the tracker's private constants (keep in step), so that the bench decides as it does:
constexpr float kClearOverlap = 0.1f;    // pose_associator.cpp: no blend above this overlap
constexpr float kReentryReach = 0.4f;    // reentry.cpp: of the view's longer side
constexpr float kReentryMargin = 0.03f;  // reentry.cpp: the best departed leads the next by this
const std::vector<float> kThresholds = {0.70f, 0.75f, 0.80f, 0.82f, 0.84f, 0.86f, 0.88f,
                                        0.90f, 0.91f, 0.92f, 0.93f, 0.94f, 0.95f, 0.97f};

struct Seen {
  int frame;  // 0-based
  int visit, person;
  Box box;
  bool overlapped;                  // another labelled pose covers > kClearOverlap of its box
  std::vector<Descriptor> pose;     // per appearance model
  std::vector<Descriptor> running;  // the visit's appearance after this pose, per model
};

cv::Point2f centre(const Box& b) {
  return {b.x + b.w / 2, b.y + b.h / 2};
}

float quantile(std::vector<float> v, double q) {
  if (v.empty()) return 0.f;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

// The area under the ROC curve: the chance that a same-person pair scores above a
// different-people pair (ties count half), one threshold-free figure for how well a model
// separates people. Sort-based (Mann-Whitney U), as the pair counts run to 10^5.
double rocArea(std::vector<float> same, std::vector<float> other) {
  if (same.empty() || other.empty()) return 0.0;
  std::sort(other.begin(), other.end());
  double wins = 0;
  for (float v : same) {
    const auto lo = std::lower_bound(other.begin(), other.end(), v);
    const auto hi = std::upper_bound(lo, other.end(), v);
    wins += static_cast<double>(lo - other.begin()) + 0.5 * static_cast<double>(hi - lo);
  }
  return wins / (static_cast<double>(same.size()) * static_cast<double>(other.size()));
}

double share(const std::vector<float>& v, float threshold) {
  if (v.empty()) return 0.0;
  return 100.0 * std::count_if(v.begin(), v.end(), [&](float x) { return x >= threshold; }) /
         v.size();
}

std::map<int, int> personOfVisit(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error("cannot open " + file);
  std::map<int, int> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    int visit = 0, person = 0;
    char comma = 0;
    std::istringstream(line) >> visit >> comma >> person;
    out[visit] = person;
  }
  return out;
}

// One re-entry decision: a visit's look against the departed within reach.
struct Reentry {
  int visit, person;
  double gap_s = -1;   // since the same person's departed visit ended; < 0: none
  float own = -2.f;    // similarity to that visit
  float wrong = -2.f;  // best other person's
  float best = -2.f, second = -2.f;
  bool best_is_own = false;  // best is own (ties go to wrong)
  int candidates = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Re-identification: how well the appearance models tell people apart"};
  std::string video = JOINTFLOW_VTEST_AVI, labels = JOINTFLOW_VTEST_LABELS,
              out_path = "docs/reid-bench.md", backend = "default";
  app.add_option("--video", video, "video with people walking")->capture_default_str();
  app.add_option("--labels", labels, "identity labels: visits/, persons/, visits.txt")
      ->capture_default_str();
  app.add_option("--backend", backend, "spatial model's engine (default, openvino, ...)")
      ->capture_default_str();
  app.add_option("--out", out_path, "Markdown file to write")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::vector<AppearanceModel> models = {AppearanceModel::kFeatures,
                                               AppearanceModel::kFeaturesColour};
  try {
    const mot::Frames truth = mot::readGroundTruth(labels + "/visits").at(0).frames;
    const std::map<int, int> person_of = personOfVisit(labels + "/visits.txt");
    cv::VideoCapture capture(video);
    if (!capture.isOpened()) throw Error("cannot open " + video);
    const double fps = capture.get(cv::CAP_PROP_FPS) > 0 ? capture.get(cv::CAP_PROP_FPS) : 10.0;
    const TrackerSettings s;  // the spatial model and thresholds jointflow-track runs with
    EngineOptions engine = s.engine;
    engine.backend = parseEnum<DnnBackend>(backend);
    const auto spatial = createSpatialModel(s.model_type, s.spatial, engine);
    JointThresholds thresholds;
    thresholds.fill(s.joint_threshold);

    std::vector<Seen> seen;
    cv::Mat frame;
    cv::Size view;
    for (int i = 0; i < static_cast<int>(truth.size()) && capture.read(frame); ++i) {
      view = frame.size();
      const SpatialResult r = spatial->estimate(frame);
      const auto& boxes = truth[i];
      // Greedy one-to-one by IoU, pairs below 0.5 never.
      std::vector<std::tuple<float, int, int>> pairs;
      for (size_t p = 0; p < r.poses.size(); ++p)
        for (size_t b = 0; b < boxes.size(); ++b) {
          const Box label{static_cast<float>(boxes[b].x), static_cast<float>(boxes[b].y),
                          static_cast<float>(boxes[b].w), static_cast<float>(boxes[b].h)};
          const float v = iou(r.poses[p].box, label);
          if (v >= 0.5f) pairs.emplace_back(v, static_cast<int>(p), static_cast<int>(b));
        }
      std::sort(pairs.rbegin(), pairs.rend());
      std::vector<int> label_of(r.poses.size(), -1), which;
      std::vector<bool> taken(boxes.size(), false);
      for (const auto& [v, p, b] : pairs)
        if (label_of[p] < 0 && !taken[b]) {
          label_of[p] = b;
          taken[b] = true;
          which.push_back(p);
        }
      std::vector<std::vector<Descriptor>> per_model;
      for (AppearanceModel m : models)
        per_model.push_back(
            describeAppearance(r.poses, which, r.features, r.grid_to_frame, frame, thresholds, m));
      for (int p : which) {
        const Box& box = r.poses[p].box;
        bool overlapped = false;
        for (int o : which)
          overlapped |=
              o != p && intersectionArea(box, r.poses[o].box) > kClearOverlap * box.area();
        const int visit = static_cast<int>(boxes[label_of[p]].id);
        Seen v{i, visit, person_of.at(visit), box, overlapped, {}, {}};
        for (const auto& d : per_model) v.pose.push_back(d[p]);
        seen.push_back(std::move(v));
      }
      if ((i + 1) % 100 == 0) std::cerr << "reid-bench: frame " << i + 1 << "\n";
    }

    // Each visit's running appearance, pose by pose (seen is in frame order).
    std::map<int, std::vector<int>> of_visit;  // visit -> indices into seen
    for (size_t k = 0; k < seen.size(); ++k) {
      Seen& v = seen[k];
      std::vector<int>& mine = of_visit[v.visit];
      v.running = mine.empty() ? v.pose : seen[mine.back()].running;
      if (!mine.empty() && !v.overlapped)
        for (size_t m = 0; m < models.size(); ++m) blendAppearance(v.running[m], v.pose[m], 0.9f);
      mine.push_back(static_cast<int>(k));
    }
    std::vector<std::vector<int>> at_frame(truth.size());
    for (size_t k = 0; k < seen.size(); ++k) at_frame[seen[k].frame].push_back(static_cast<int>(k));

    // Within a visit: rank-1 at 1 s and 2 s, and the pairs 1-2 s apart for the ROC.
    std::ostringstream rank_table;
    rank_table << "| appearance model | gap | queries | rank-1 | same person: median, 10th pct | "
                  "different people: median, 90th pct |\n|---|---|---:|---:|---|---|\n";
    std::vector<std::vector<float>> roc_same(models.size()), roc_other(models.size());
    const int gap_1s = static_cast<int>(std::lround(fps));
    for (size_t m = 0; m < models.size(); ++m)
      for (int gap = gap_1s; gap <= 2 * gap_1s; ++gap) {
        int queries = 0, first = 0;
        std::vector<float> same, other;
        for (const Seen& a : seen) {
          if (a.frame + gap >= static_cast<int>(at_frame.size())) continue;
          float best_same = -2.f, best_other = -2.f;
          for (int k : at_frame[a.frame + gap]) {
            const Seen& b = seen[k];
            const float sim = appearanceSimilarity(a.running[m], b.pose[m]);
            if (b.visit == a.visit)
              best_same = sim, same.push_back(sim);
            else if (b.person != a.person)
              best_other = std::max(best_other, sim), other.push_back(sim);
          }
          if (best_same > -2.f && best_other > -2.f) ++queries, first += best_same > best_other;
        }
        roc_same[m].insert(roc_same[m].end(), same.begin(), same.end());
        roc_other[m].insert(roc_other[m].end(), other.begin(), other.end());
        if (gap != gap_1s && gap != 2 * gap_1s) continue;
        rank_table << std::fixed << std::setprecision(0) << "| " << toString(models[m]) << " | "
                   << gap / fps << " s | " << queries << " | "
                   << (queries ? 100.0 * first / queries : 0.0) << " % | " << std::setprecision(2)
                   << quantile(same, 0.5) << ", " << quantile(same, 0.1) << " | "
                   << quantile(other, 0.5) << ", " << quantile(other, 0.9) << " |\n";
      }

    // Re-entry: each visit's look once the tracker decides against the departed within reach.
    const size_t look_after = static_cast<size_t>(s.min_track_length);
    const float reach = kReentryReach * static_cast<float>(std::max(view.width, view.height));
    std::vector<std::vector<Reentry>> reentries(models.size());
    for (const auto& [visit, mine] : of_visit) {
      const Seen& start = seen[mine[std::min(look_after, mine.size()) - 1]];
      const Seen& born = seen[mine.front()];
      for (size_t m = 0; m < models.size(); ++m) {
        Reentry q{visit, born.person};
        // The tracker keeps one departed entry per id, the newest: per person, the visit that
        // ended last (a person's earlier visit must not count as a second, "other" candidate).
        std::map<int, const Seen*> departed;
        for (const auto& [other, theirs] : of_visit) {
          const Seen& last = seen[theirs.back()];
          const double gone_s = (born.frame - last.frame) / fps;
          const Seen*& newest = departed[last.person];
          if (gone_s > 0 && gone_s <= s.reentry_time && (!newest || newest->frame < last.frame))
            newest = &last;
        }
        for (const auto& [person, newest] : departed) {
          if (!newest) continue;
          const Seen& last = *newest;
          const double gone_s = (born.frame - last.frame) / fps;
          const cv::Point2f gap = centre(last.box) - centre(born.box);
          if (std::hypot(gap.x, gap.y) > reach) continue;
          const float sim = appearanceSimilarity(last.running[m], start.running[m]);
          ++q.candidates;
          if (last.person == q.person) {
            q.own = sim, q.gap_s = gone_s;
          } else {
            q.wrong = std::max(q.wrong, sim);
          }
          q.second = std::max(q.second, std::min(q.best, sim));
          q.best = std::max(q.best, sim);
        }
        q.best_is_own = q.own > q.wrong;
        if (q.candidates > 0) reentries[m].push_back(q);
      }
    }
    std::ostringstream reentry_table, reentry_rank;
    reentry_table << "| visit | person | gone (s) | candidates | "
                  << "features: own, best wrong | features-colour: own, best wrong |\n"
                  << "|---:|---:|---:|---:|---|---|\n";
    const auto sim_text = [](float v) {
      std::ostringstream o;
      if (v > -2.f)
        o << std::fixed << std::setprecision(2) << v;
      else
        o << "-";
      return o.str();
    };
    for (size_t k = 0; k < reentries[0].size(); ++k) {
      const Reentry& a = reentries[0][k];
      const Reentry& b = reentries[1][k];
      reentry_table << "| " << a.visit << " | " << a.person << " | "
                    << (a.gap_s >= 0 ? sim_text(static_cast<float>(a.gap_s)) : "-") << " | "
                    << a.candidates << " | " << sim_text(a.own) << ", " << sim_text(a.wrong)
                    << " | " << sim_text(b.own) << ", " << sim_text(b.wrong) << " |\n";
    }
    for (size_t m = 0; m < models.size(); ++m) {
      int returning = 0, first = 0;
      for (const Reentry& q : reentries[m])
        if (q.own > -2.f) ++returning, first += q.best_is_own;
      reentry_rank << "| " << toString(models[m]) << " | " << returning << " | " << first << " |\n";
    }

    // ROC: true and false accepts per threshold, both uses.
    std::ostringstream roc;
    roc << "| threshold | features: same accepted | different accepted | re-entry right | "
           "re-entry wrong | features-colour: same accepted | different accepted | re-entry "
           "right | re-entry wrong |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (float t : kThresholds) {
      roc << std::fixed << std::setprecision(2) << "| " << t;
      for (size_t m = 0; m < models.size(); ++m) {
        int returning = 0, right = 0, wrong = 0;
        for (const Reentry& q : reentries[m]) {
          returning += q.own > -2.f;
          if (q.best < t || q.best - q.second < kReentryMargin) continue;
          (q.best_is_own ? right : wrong)++;
        }
        roc << std::setprecision(1) << " | " << share(roc_same[m], t) << " % | "
            << share(roc_other[m], t) << " % | " << right << "/" << returning << " | " << wrong
            << "/" << reentries[m].size();
      }
      roc << " |\n";
    }
    std::ostringstream area;
    area << "| appearance model | ROC area |\n|---|---:|\n";
    for (size_t m = 0; m < models.size(); ++m)
      area << "| " << toString(models[m]) << " | " << std::fixed << std::setprecision(3)
           << rocArea(roc_same[m], roc_other[m]) << " |\n";

    std::ofstream doc(out_path);
    doc << "# Re-identification: how well the appearance models tell people apart\n\n"
        << "Written by `bench/reid_bench.cpp`; regenerate with\n\n"
        << "    build/bench/reid-bench --backend " << backend << "\n\n"
        << "All " << truth.size() << " frames of " << video
        << " through the tracker's spatial model (default settings); each pose takes the identity"
        << " of the hand-made label box it overlaps (IoU >= 0.5, one to one; "
        << (labels == JOINTFLOW_VTEST_LABELS ? "tests/data/vtest-identity" : labels)
        << ", 11 people in 20 visits), " << seen.size() << " poses in all; poses with no label"
        << " are left out. A visit's appearance is kept as the tracker keeps a track's: blended "
        << "(0.9) pose by pose, not from poses that overlap another by more than 10 % of their "
        << "box.\n\n"
        << "## Within a visit (`reid_min_similarity`)\n\n"
        << "A visit's appearance at frame t against each pose of frame t + gap: rank-1 is the "
        << "share of queries where the visit's own pose comes first among the people present.\n\n"
        << rank_table.str() << "\n## Re-entry (`reentry_min_similarity`)\n\n"
        << "Each visit's appearance after its first " << look_after
        << " poses (when the tracker decides) against every visit that ended at most "
        << s.reentry_time
        << " s before it started (per person the newest, as the tracker keeps one "
        << "entry per id), at its end, last seen within " << kReentryReach
        << " of the view's longer side of where the new visit starts (reentry.cpp's departed). "
        << "Visits of a person's first appearance are here too (\"-\" own): any id they take is "
        << "wrong.\n\n"
        << reentry_table.str() << "\n| appearance model | returning visits | own ranked first |\n"
        << "|---|---:|---:|\n"
        << reentry_rank.str() << "\n## ROC\n\n"
        << "Same accepted / different accepted: the share of pairs 1-2 s apart within a visit "
        << "(appearance against pose) at or above the threshold, " << roc_same[1].size()
        << " same-person and " << roc_other[1].size()
        << " different-person pairs (features-colour); the tracker's position gate, which keeps "
        << "most different people out, is not applied. Re-entry right / wrong: visits that take "
        << "the own departed visit (of those returning) / a wrong one (of all with a candidate), "
        << "where the best is at or above the threshold and leads the next by " << kReentryMargin
        << ".\n\n"
        << roc.str() << "\nThe area under the curve of same against different accepted (1 is a "
        << "perfect separation, 0.5 a coin):\n\n"
        << area.str();
    std::cout << rank_table.str() << "\n"
              << reentry_table.str() << "\n"
              << reentry_rank.str() << "\n"
              << roc.str() << "\n"
              << area.str();
  } catch (const std::exception& e) {
    std::cerr << "reid-bench: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
