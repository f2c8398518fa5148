// jointflow-eval: PoseTrack metrics (mAP, MOTA, MOTP, precision, recall) of predictions against
// ground truth, equivalent to the public poseval tool by default, and the identity metrics IDF1,
// IDP, IDR as py-motmetrics computes them on poseval's events (jointflow/evaluation.hpp).
//
//   jointflow-eval --gt PATH --pred PATH [--json]
// PATH is one PoseTrack file (2017 or 2018 format) or a folder of per-sequence files; in folders,
// prediction files pair with ground-truth files by file name.
#include <iostream>

#include <CLI/CLI.hpp>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "PoseTrack evaluation (poseval-compatible): per-joint and total MOTA, MOTP, "
      "precision, recall and mAP; IDF1, IDP and IDR as py-motmetrics computes them"};
  std::string gt_path, pred_path;
  bool as_json = false;
  bool keep_last_frame = false, count_all_in_empty_frames = false, motp_matches_only = false;
  jointflow::PoseTrackEvalOptions options;
  app.add_option("--gt", gt_path, "ground truth: a PoseTrack file or a folder of them")->required();
  app.add_option("--pred", pred_path, "predictions: a PoseTrack file or a folder of them")
      ->required();
  app.add_flag("--json", as_json, "print JSON (percent) instead of tables");
  app.add_flag("--keep-last-frame", keep_last_frame,
               "track the last labelled frame too (poseval ignores it)");
  app.add_flag("--count-all-in-empty-frames", count_all_in_empty_frames,
               "a frame without predictions or ground truth counts each missed / false joint "
               "(poseval counts 1 miss + 1 false positive per joint)");
  app.add_flag("--motp-matches-only", motp_matches_only,
               "MOTP from the distances of matched joints only (poseval also sums every pair "
               "within the threshold)");
  app.add_option("--threshold", options.pckh_threshold, "match radius in head sizes (PCKh)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  options.drop_last_frame = !keep_last_frame;
  options.empty_frame_one_miss = !count_all_in_empty_frames;
  options.motp_all_events = !motp_matches_only;

  try {
    const jointflow::PoseTrackEvalResult result =
        jointflow::evaluatePoseTrackFiles(gt_path, pred_path, options);
    if (as_json) {
      std::cout << jointflow::poseTrackResultJson(result) << "\n";
    } else {
      std::cout << jointflow::formatPoseTrackTables(result);
    }
  } catch (const jointflow::Error& e) {
    std::cerr << "jointflow-eval: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
