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
  if (!out_path.empty()) std::ofstream(out_path) << table.str();
  return 0;
}
