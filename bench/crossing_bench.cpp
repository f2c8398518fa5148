// crossing-bench: do two people keep their ids where they cross or meet? Synthetic walkers with the
// Bonn train people's real articulation (bench/crossings.hpp), every similarity that needs no
// image (oks, iou, pckh; auto is oks on frames this close), per kind of case and offset.
//
//   crossing-bench [--data DIR] [--pairs N] [--seed S] [--out FILE] [--failures]
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "crossings.hpp"
#include "jointflow/setting_enums.hpp"

using namespace jointflow;
using namespace jointflow::bench;

int main(int argc, char** argv) {
  CLI::App app{"Two walkers crossing or meeting with real articulation: ids kept, swapped, new"};
  std::string data = JOINTFLOW_DEFAULT_DATA_DIR;
  int pairs = 100;
  unsigned seed = 1;
  std::string out_path;
  bool show_failures = false;
  std::vector<std::string> similarities{"auto", "oks", "iou", "pckh"};
  app.add_option("--data", data, "Data folder (bonn-posetrack/annotations/train inside)");
  app.add_option("--pairs", pairs, "Pairs of train people");
  app.add_option("--seed", seed, "Random seed");
  app.add_option("--out", out_path, "Markdown table to write");
  app.add_option("--similarities", similarities, "Similarities")->delimiter(',');
  app.add_flag("--failures", show_failures, "Print every case not kept");
  std::string trace;
  app.add_option("--trace", trace, "Print frame by frame the cases of these two train people");
  CLI11_PARSE(app, argc, argv);

  const std::string train = data + "/bonn-posetrack/annotations/train";
  const std::vector<float> offsets{0.1f, 0.25f, 0.4f};
  const CrossingOptions options;
  const std::vector<CrossingCase> cases = makeCrossings(train, pairs, offsets, options, seed);
  if (cases.empty()) {
    std::cerr << "no cases: " << train << " holds no train people\n";
    return 1;
  }
  std::ostringstream table;
  table << "| similarity | kind | offset | cases | kept | swapped | new id | lost | switches |\n"
        << "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& name : similarities) {
    TrackerSettings s;
    s.similarity = parseEnum<SimilarityType>(name);
    for (const CrossingKind kind : {CrossingKind::kCross, CrossingKind::kMeet})
      for (const float offset : offsets) {
        std::vector<CrossingCase> subset;
        for (const CrossingCase& c : cases)
          if (c.kind == kind && c.offset == offset) subset.push_back(c);
        std::vector<std::string> failures;
        std::vector<CrossingCase> traced;
        for (const CrossingCase& c : subset)
          if (c.source == trace) traced.push_back(c);
        if (!traced.empty()) trackCrossings(traced, s, nullptr, &std::cerr);
        const CrossingOutcome o = trackCrossings(subset, s, &failures);
        table << "| " << name << " | " << (kind == CrossingKind::kCross ? "cross" : "meet") << " | "
              << std::setprecision(2) << offset << " | " << o.cases << " | " << o.kept << " | "
              << o.swapped << " | " << o.new_id << " | " << o.lost << " | " << o.switches << " |\n";
        if (show_failures)
          for (const std::string& f : failures) std::cerr << name << ": " << f << "\n";
      }
  }
  std::cout << table.str();
  if (!out_path.empty()) {
    std::ofstream out(out_path);
    out << "# Crossings: two people who cross or meet\n\n"
        << "Written by `bench/crossing_bench.cpp`; regenerate with\n\n"
        << "    build/bench/crossing-bench --pairs " << pairs << " --seed " << seed
        << " --out docs/crossings.md\n\n"
        << "Two walkers " << options.height << " px tall, " << options.speed
        << " heights per second, seen at " << options.fps
        << " frames/s, with the articulation of two Bonn PoseTrack train people (their ground "
           "truth: real motion, no images), come towards each other on lines `offset` heights "
           "apart; the lower one, nearer the camera, is in front. *cross*: they pass each other. "
           "*meet*: they stop a third of a height apart for "
        << options.linger
        << " s and go back the way they came. Joints of the one behind that fall inside the box of "
           "the one in front (grown by "
        << options.cover_margin << " heights) are not detected, others are missed with probability "
        << options.miss_joint << " and jittered by " << options.jitter
        << " heights; a person with fewer than " << options.min_visible
        << " joints is not detected. No images, so no appearance: this is what position, pose "
           "and motion alone keep. `bench/crossings.hpp` builds the cases; tests/bench's "
           "[crossing] cases hold the default to these figures.\n\n"
        << "*kept*: both leave with the ids they came with; *swapped*: someone leaves with the "
           "other's id; *new id*: someone leaves under an id new to the case; *lost*: someone is "
           "not reported at the end; *switches*: times a person was reported under another id "
           "than on their previous frame (a swap undone counts 2).\n\n"
        << table.str();
  }
  return 0;
}
