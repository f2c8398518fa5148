// reid-bench: how well each appearance model of re-identification (TrackerSettings::reid) tells
// people apart on real frames. vtest.avi is tracked at its full frame rate with the default
// tracker (reid off, so the labels do not depend on what is measured); its confirmed tracks are
// the labels. For every person seen at frame t, the people of frame t + gap (gap 1 s and 2 s) are
// ranked by appearance similarity to it: "rank-1" is the share where the same track ranks first.
// Also the similarity distribution of same-person and different-person pairs, which sets
// reid_min_similarity. Writes docs/reid-bench.md.
//
//   build/bench/reid-bench [--video FILE] [--frames N] [--out FILE]
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <opencv2/videoio.hpp>

#include "jointflow/appearance.hpp"
#include "jointflow/tracker.hpp"

using namespace jointflow;

namespace {

struct Seen {
  int frame;
  std::int64_t id;
  std::vector<Descriptor> descriptors;  ///< one per appearance model compared
};

float quantile(std::vector<float> v, double q) {
  if (v.empty()) return 0.f;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Re-identification: how well the appearance models tell people apart"};
  std::string video = JOINTFLOW_VTEST_AVI, out_path = "docs/reid-bench.md";
  int frames = 300;
  app.add_option("--video", video, "video with people walking")->capture_default_str();
  app.add_option("--frames", frames, "frames to track")->capture_default_str();
  app.add_option("--out", out_path, "Markdown file to write")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::vector<AppearanceModel> models = {AppearanceModel::kFeatures,
                                               AppearanceModel::kFeaturesColour};
  try {
    cv::VideoCapture capture(video);
    if (!capture.isOpened()) throw Error("cannot open " + video);
    const double fps = capture.get(cv::CAP_PROP_FPS) > 0 ? capture.get(cv::CAP_PROP_FPS) : 10.0;
    TrackerSettings s;
    s.model_type = ModelType::kMoveNet;
    s.spatial.input_size = InputSize::parse("native");  // vtest's people are 40-100 px tall
    s.reid = AppearanceModel::kOff;
    Tracker tracker(s);
    const auto spatial = createSpatialModel(s.model_type, s.spatial);
    JointThresholds thresholds;
    thresholds.fill(s.joint_threshold);
    std::vector<Seen> seen;
    cv::Mat frame;
    const int step = std::max(1, static_cast<int>(std::lround(fps / 2)));  // every 0.5 s
    for (int i = 0; i < frames && capture.read(frame); ++i) {
      const SpatialResult r = spatial->estimate(frame);
      const auto tracked = tracker.process(r, frame, PixelOrder::kBGR, i / fps);
      if (i % step != 0) continue;
      Poses poses;
      std::vector<int> which;
      for (const TrackedPose& tp : tracked)
        if (!tp.tentative && tp.pose.score >= 0.3f) {
          which.push_back(static_cast<int>(poses.size()));
          poses.push_back(tp.pose);
        }
      std::vector<std::vector<Descriptor>> per_model;
      for (AppearanceModel m : models)
        per_model.push_back(
            describeAppearance(poses, which, r.features, r.grid_to_frame, frame, thresholds, m));
      size_t k = 0;
      for (const TrackedPose& tp : tracked) {
        if (tp.tentative || tp.pose.score < 0.3f) continue;
        Seen v{i, tp.track_id, {}};
        for (const auto& d : per_model) v.descriptors.push_back(d[k]);
        seen.push_back(std::move(v));
        ++k;
      }
      if ((i + 1) % 50 == 0) std::cerr << "reid-bench: frame " << i + 1 << "/" << frames << "\n";
    }

    std::ostringstream table;
    table << "| appearance model | gap | queries | rank-1 | same person: median, 10th pct | "
             "different people: median, 90th pct |\n|---|---|---:|---:|---|---|\n";
    for (size_t m = 0; m < models.size(); ++m)
      for (const double gap_s : {1.0, 2.0}) {
        const int gap = static_cast<int>(std::lround(gap_s * fps));
        int queries = 0, first = 0;
        std::vector<float> same, other;
        for (const Seen& a : seen) {
          float best_same = -2.f, best_other = -2.f;
          for (const Seen& b : seen) {
            if (b.frame != a.frame + gap) continue;
            const float sim = appearanceSimilarity(a.descriptors[m], b.descriptors[m]);
            if (b.id == a.id) {
              best_same = sim;
              same.push_back(sim);
            } else {
              best_other = std::max(best_other, sim);
              other.push_back(sim);
            }
          }
          if (best_same > -2.f && best_other > -2.f) {
            ++queries;
            first += best_same > best_other;
          }
        }
        table << std::fixed << std::setprecision(2) << "| " << toString(models[m]) << " | " << gap_s
              << " s | " << queries << " | " << std::setprecision(0)
              << (queries ? 100.0 * first / queries : 0.0) << " % | " << std::setprecision(2)
              << quantile(same, 0.5) << ", " << quantile(same, 0.1) << " | " << quantile(other, 0.5)
              << ", " << quantile(other, 0.9) << " |\n";
      }
    std::ofstream doc(out_path);
    doc << "# Re-identification: how well the appearance models tell people apart\n\n"
        << "Written by `bench/reid_bench.cpp`; regenerate with\n\n"
        << "    build/bench/reid-bench --frames " << frames << "\n\n"
        << "The first " << frames << " frames of " << video
        << " tracked at full rate (MoveNet native, reid off); its confirmed tracks are the labels."
        << " For each person seen at frame t (every 0.5 s), the people of frame t + gap are ranked"
        << " by appearance similarity: rank-1 is the share of queries where the same track comes "
        << "first. The two distributions set `reid_min_similarity` (docs/tracking.md).\n\n"
        << table.str();
    std::cout << table.str();
  } catch (const std::exception& e) {
    std::cerr << "reid-bench: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
