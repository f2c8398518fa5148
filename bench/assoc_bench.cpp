// assoc-bench: association only, on real human motion with identities (the Bonn PoseTrack train
// ground truth, no images). The ground-truth poses get simulated detector noise (joint jitter,
// missed joints, missed and false people), every similarity gets the same detections at frame
// strides 1-4, and the tracks are scored with the poseval-equivalent evaluation
// (jointflow/evaluation.hpp). "tff-oracle" is the TFF rendered from the ground truth (paper
// Eq. 2-4), i.e. what a perfect TFF network would give. Also times the association of 30 by 30
// and of 20 by 20 people with the TFF integral on one core. The simulation and the timing live in
// bench/assoc_sim.cpp (shared with bench/identity.cpp).
//
//   assoc-bench --data DIR [--stride N] [--json] [--seed S]
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "assoc_sim.hpp"
#include "jointflow/error.hpp"

using namespace jointflow;
using namespace jointflow::bench;

namespace {

std::string defaultDataDir() {
  const char* env = std::getenv("JOINTFLOW_DATA");
  const std::string root = env && *env ? env : JOINTFLOW_DEFAULT_DATA_DIR;
  return root + "/bonn-posetrack/annotations/train";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Association benchmark on ground-truth motion with simulated detector noise"};
  std::string data = defaultDataDir();
  int stride = 0;
  bool json = false;
  unsigned seed = 2018;
  Noise noise;
  TrackerSettings settings;  // the defaults, except where an option below says otherwise
  bool paper = false;
  app.add_option("--data", data, "folder of PoseTrack 2018 ground-truth files with track ids");
  app.add_option("--stride", stride, "frame stride 1-4 (default: all four)")
      ->check(CLI::Range(1, 4));
  app.add_flag("--json", json, "print {\"results\": [...]} instead of tables");
  app.add_option("--seed", seed, "seed of the simulated detector noise");
  app.add_option("--jitter", noise.jitter, "joint jitter, standard deviation in head sizes");
  app.add_option("--miss-joint", noise.miss_joint, "probability of a missed joint");
  app.add_option("--miss-person", noise.miss_person, "probability of a missed person");
  app.add_option("--false-person", noise.false_person, "false people per frame (mean)");
  app.add_option("--min-potential", settings.min_potential, "TrackerSettings::min_potential");
  app.add_option("--tau-delta", settings.tau_delta, "TrackerSettings::tau_delta, px");
  app.add_option("--lost-time", settings.lost_time, "TrackerSettings::lost_time, s");
  std::string matcher = "greedy";
  app.add_option("--matcher", matcher, "greedy or optimal");
  app.add_flag("--paper", paper,
               "the paper's association only: no geometric fallback, no coasting, min potential 0");
  CLI11_PARSE(app, argc, argv);
  settings.matcher = parseEnum<Matcher>(matcher);
  if (paper) {
    settings.geometric_fallback = false;
    settings.min_potential = 0.f;
    settings.lost_time = settings.tentative_lost_time = 0.f;
  }

  if (!std::filesystem::exists(data)) {
    std::cerr << "assoc-bench: SKIPPED: " << data
              << " is absent (pass --data or set JOINTFLOW_DATA)\n";
    if (json) std::cout << "{\"results\": [], \"skipped\": \"data absent\"}\n";
    return 0;
  }
  try {
    const std::size_t num_sequences = posetrack::listSequenceFiles(data).size();
    const std::vector<std::string> similarities = {"oks", "iou", "pckh", "tff-oracle"};
    std::vector<int> strides = {1, 2, 3, 4};
    if (stride) strides = {stride};

    nlohmann::json results = nlohmann::json::array();
    std::ostringstream table;
    table << std::fixed << std::setprecision(1);
    table
        << "| similarity | stride | MOTA % | IDF1 % | id switches (persons) | id switches (joints, "
           "poseval) |\n"
        << "|---|---|---|---|---|---|\n";
    for (int s : strides) {
      const std::vector<SimSequence> sims = simulateFolder(data, s, noise, seed + s);
      for (const std::string& name : similarities) {
        const SimRunResult r = trackSimulated(sims, name, settings);
        results.push_back({{"similarity", name},
                           {"stride", s},
                           {"mota", r.eval.total.mota},
                           {"idf1", r.eval.total.idf1},
                           {"id_switches", r.id_switches},
                           {"joint_id_switches", r.joint_id_switches}});
        table << "| " << name << " | " << s << " | " << r.eval.total.mota << " | "
              << r.eval.total.idf1 << " | " << r.id_switches << " | " << r.joint_id_switches
              << " |\n";
      }
    }
    const AssociationTiming timing = timeTffPotentials(30, settings.line_samples);
    const AssociationTiming timing20 = timeTffPotentials(20, settings.line_samples);
    if (json) {
      std::cout << nlohmann::json{{"results", results},
                                  {"tff_30x30_ms",
                                   {{"potentials", timing.potentials_ms},
                                    {"with_greedy", timing.with_greedy_ms},
                                    {"wall", timing.wall_ms},
                                    {"best_with_greedy", timing.best_ms}}},
                                  {"tff_20x20_ms",
                                   {{"potentials", timing20.potentials_ms},
                                    {"with_greedy", timing20.with_greedy_ms},
                                    {"wall", timing20.wall_ms},
                                    {"best_with_greedy", timing20.best_ms}}}}
                       .dump(1)
                << "\n";
    } else {
      std::cout << "Association on " << num_sequences << " sequences of " << data
                << "\nnoise: jitter " << noise.jitter << " head sizes, missed joints "
                << noise.miss_joint << ", missed people " << noise.miss_person
                << ", false people/frame " << noise.false_person << ", seed " << seed << "\n\n"
                << table.str() << "\n"
                << std::setprecision(3) << "TFF association of 30 x 30 people (17 joints x "
                << settings.line_samples
                << " samples), median of 200 runs, CPU time of one core: " << timing.potentials_ms
                << " ms potentials, " << timing.with_greedy_ms << " ms with greedy matching ("
                << timing.wall_ms << " ms wall clock); fastest run " << timing.best_ms
                << " ms\n20 x 20 people: " << timing20.potentials_ms << " ms potentials, "
                << timing20.with_greedy_ms << " ms with greedy matching (" << timing20.wall_ms
                << " ms wall clock); fastest run " << timing20.best_ms << " ms\n";
    }
  } catch (const Error& e) {
    std::cerr << "assoc-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
