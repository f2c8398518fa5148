// identity-bench: does a person keep one id? Measured per similarity (auto, tff, oks, iou, pckh,
// flow) at the default TrackerSettings, on
//   1. variants of the Bonn test sequence with exact ground truth (bench/variants.hpp): the still
//      sequence at strides 1-3, reversed play, dropped frames, camera shake, pan, zoom, an
//      occluder bar sweeping over the people, small people. The spatial model (MoveNet) runs once
//      per output frame; every similarity's jointflow::Tracker gets the same SpatialResult
//      (bench/cached_tracking.hpp). Scores: poseval's MOTA and joint id switches, IDF1 as
//      py-motmetrics computes it (jointflow/evaluation.hpp). For the occluder: the share of the
//      people hidden by the bar who come back under the id they had before;
//   2. the Bonn train motion with simulated detections (bench/assoc_sim.hpp; no images, so no
//      tff network and no flow: tff-oracle is the TFF rendered from the ground truth);
//   3. vtest.avi (no ground truth): distinct ids per person who appears, people counted by eye;
//   4. live pipelines (real-time pacing, leaky queue before jointflowtrack) against the offline
//      runs of the same clips (bench/live_cases.hpp): the Bonn sequence as a live camera, scored
//      against its ground truth, per similarity and engine; vtest.avi, distinct ids;
//   5. the association time per frame for 20 people.
// Writes docs/identity.md and the raw figures as JSON (docs/identity.json) for later comparison.
//
//   identity-bench [--data DIR] [--vtest FILE] [--out FILE] [--json FILE] [--cases LIST]
//                  [--similarities LIST] [--vtest-frames N] [--live-frames N] [--fps F]
//                  [--live-bonn-frames N] [--live-bonn-backends LIST]
//                  [--predictions DIR] [--vtest-sheet IMAGE [--sheet-similarity NAME]]
//                  [--set NAME=VALUE ...] [association options]
//
// The cases are in identity_cases.cpp, the document and the JSON in identity_document.cpp; here:
// the options, which cases --cases picks, and the order of the run.
#include <gst/gst.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "association_options.hpp"
#include "identity_cases.hpp"
#include "identity_document.hpp"
#include "setting_args.hpp"
#include "text_format.hpp"

using namespace jointflow;
using namespace jointflow::bench;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// People in vtest.avi (795 frames at 10 frames/s), counted by eye once, for this benchmark (the
// counts: kVtestPeople* and kVtestVisits* in identity_cases.hpp): every 10th frame viewed at 0.7x
// in order (2 x 2 contact sheets), each person noted with the frame and border of entry and exit
// and described by clothing; entries and exits were then checked on space-time slices of the
// left, right, top and bottom borders (|frame - median| along a strip, one column per frame: a
// person crossing is a dark streak), and people who leave and come back were told apart or matched
// on full-resolution crops. Result: 11 people in 20 visits (a visit: from entering the view to
// leaving it). The people: a man in a leather jacket with a white paper (in view at frame 0; out
// 208-228, 402-505 and 612-690), a man with glasses and jeans (frame 0; out 519-570), a man in a
// black coat (frame 0; out 145-218), a man in a red and navy jacket and a blonde woman in a black
// coat (enter at 10 and 17, out together 365-505), a bald man in jeans (enters at 40; out 390-462),
// a small figure on the far path at the top left (67-170, about 25 px tall), a woman in a white
// hood (115-215), a man in a striped sweater (130-281), a woman in a red top (enters at 420; out
// 575-608 at the left), a grey-haired man in a blue jacket (655-742). Frames 1-300: 9 of them, in
// 11 visits. Re-identifying a person across a visit needs appearance (issue 11); ids per visit is
// what a tracker without it can reach at best.

namespace {

/// The 1-minute load average (other jobs on the machine slow the timings down).
double loadAverage() {
  double load[1] = {std::nan("")};
  return getloadavg(load, 1) == 1 ? load[0] : std::nan("");
}

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  gst_init(&argc, &argv);
  CLI::App app{"Identity benchmark: ids under camera motion, occlusion, dropped frames, reversal"};
  IdentityOptions options;
  options.data = JOINTFLOW_DEFAULT_DATA_DIR;
  options.vtest = JOINTFLOW_VTEST_AVI;
  std::string out_path = "docs/identity.md", json_path = "docs/identity.json";
  std::string cases_text = "all", similarities_text = "auto,tff,oks,iou,pckh,flow";
  app.add_option("--data", options.data, "data folder (bonn-posetrack/ inside)")
      ->capture_default_str();
  app.add_option("--vtest", options.vtest, "vtest.avi")->capture_default_str();
  app.add_option("--out", out_path, "Markdown file to write")->capture_default_str();
  app.add_option("--json", json_path, "JSON file of the raw figures")->capture_default_str();
  app.add_option(
         "--cases", cases_text,
         "comma-separated: Bonn variant names, camera, live-bonn, bonn-train, vtest, live, timing; "
         "or all")
      ->capture_default_str();
  app.add_option("--similarities", similarities_text, "similarities")->capture_default_str();
  app.add_option("--vtest-frames", options.vtest_frames, "frames of vtest.avi (0 = all)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--live-frames", options.live_frames,
                 "frames of vtest.avi's live check (real time)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  LiveBonnOptions& live_bonn = options.live_bonn;
  app.add_option("--live-bonn-frames", live_bonn.frames,
                 "frames of the Bonn live clip (forward-backward play, at --fps)")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  std::string live_bonn_backends = "opencv,openvino";
  app.add_option("--live-bonn-backends", live_bonn_backends,
                 "jointflowtrack backends of the Bonn live case")
      ->capture_default_str();
  app.add_option("--fps", options.variant.fps,
                 "frame rate of the Bonn sequence (it is not recorded), s of stream")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--joint-threshold", options.joint_threshold,
                 "joints scoring below are not written (poseval counts every written joint)")
      ->capture_default_str();
  AssociationOptions association;
  association.addTo(app);
  std::vector<std::string> assignments;
  addSetOption(app, assignments,
               "; the live cases pass them to the element, but for backend (--live-bonn-backends)");
  app.add_option("--seed", options.variant.seed, "seed of the shake, the drops and the noise")
      ->capture_default_str();
  app.add_option("--predictions", options.predictions_dir,
                 "folder to write each Bonn case's ground truth and each similarity's tracks to, "
                 "in PoseTrack 2018 form (DIR/CASE/gt.json, DIR/CASE/SIMILARITY.json), for "
                 "jointflow-eval or a look at where ids switch");
  options.sheet_similarity = toString(TrackerSettings{}.similarity);
  app.add_option("--vtest-sheet", options.vtest_sheet,
                 "Image (PNG, JPEG) to draw vtest.avi's tracks of one similarity to: a crop per "
                 "id and visit, for a look at who came back under which id");
  app.add_option("--sheet-similarity", options.sheet_similarity,
                 "the similarity --vtest-sheet draws (one of --similarities)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  options.similarities = splitList(similarities_text);
  live_bonn.backends = splitList(live_bonn_backends);
  live_bonn.similarities = options.similarities;
  live_bonn.properties = association.elementProperties();
  // Not the backend: the live cases run each of --live-bonn-backends and say which.
  for (const std::string& a : assignments)
    if (a.rfind("backend=", 0) != 0)
      live_bonn.properties += (live_bonn.properties.empty() ? "" : " ") + a;
  live_bonn.joint_threshold = options.joint_threshold;
  if (const auto& listed = options.similarities;
      !options.vtest_sheet.empty() &&
      std::find(listed.begin(), listed.end(), options.sheet_similarity) == listed.end()) {
    std::cerr << "identity-bench: --sheet-similarity " << options.sheet_similarity
              << " is not one of --similarities (" << similarities_text << ")\n";
    return 2;
  }
  const std::vector<std::string> wanted = splitList(cases_text);
  auto want = [&](const std::string& name) {
    return std::find(wanted.begin(), wanted.end(), "all") != wanted.end() ||
           std::find(wanted.begin(), wanted.end(), name) != wanted.end();
  };
  const auto start = Clock::now();
  const double load_at_start = loadAverage();

  try {
    IdentityRun run;
    run.options = options;
    // main's defaults: only the similarity, the --set settings and the association options change
    applySettings(run.defaults, assignments);
    association.applyTo(run.defaults);
    run.trackers = std::make_unique<SimilarityTrackers>(options.similarities, run.defaults);
    run.model =
        createSpatialModel(run.defaults.model_type, run.defaults.spatial, run.defaults.engine);
    run.log = [&](const std::string& text) {
      std::cerr << "[" << fixed(secondsSince(start), 0) << " s] " << text << std::endl;
    };
    // Scratch space of the live cases (clips, JSON files), removed by them.
    run.scratch = fs::temp_directory_path() / ("identity-bench-" + std::to_string(getpid()));
    const std::string bonn_root = options.data + "/bonn-posetrack";
    const std::string bonn_gt = bonn_root + "/annotations/test/060470979_bonn_test.json";
    run.bonn = readBonnSequence(bonn_gt, bonn_root, options.variant);

    IdentityFigures figures;
    if (!run.bonn) figures.notes = "Bonn test sequence: not run (" + bonn_gt + " is absent).\n\n";
    for (const IdentityCase& c : identityCases(run))
      if (want(c.name) || (!c.group.empty() && want(c.group))) c.run(run, figures);

    IdentityRunInfo info;
    info.command =
        std::string(argv[0]) + " --cases " + cases_text + " " + association.commandLine();
    info.command += setArguments(assignments);
    info.model = toString(run.model->type());
    info.input_size = run.defaults.spatial.input_size.toString();
    info.json_name = fs::path(json_path).filename().string();
    info.seconds = secondsSince(start);
    info.load_start = load_at_start;
    info.load_end = loadAverage();
    const std::string doc = identityMarkdown(figures, options, info);
    for (const std::string& path : {out_path, json_path}) {
      const fs::path parent = fs::path(path).parent_path();
      if (!parent.empty()) fs::create_directories(parent);
    }
    std::ofstream(out_path) << doc;
    std::ofstream(json_path) << identityJson(figures, options, info).dump(1) << "\n";
    std::cout << doc;
    run.log("wrote " + out_path + " and " + json_path);
  } catch (const std::exception& e) {
    std::cerr << "identity-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
