// jointflow-eval: PoseTrack metrics (mAP, MOTA, MOTP, precision, recall) of predictions against
// ground truth, equivalent to the public poseval tool by default, and the identity metrics IDF1,
// IDP, IDR as py-motmetrics computes them on poseval's events (jointflow/evaluation.hpp).
//
//   jointflow-eval --gt PATH --pred PATH [--json]
// PATH is one PoseTrack file (2017 or 2018 format) or a folder of per-sequence files; in folders,
// prediction files pair with ground-truth files by file name.
//
//   jointflow-eval --mot-gt DIR --pred PATH [--json] [--min-visibility V] [--min-score S]
// Boxes in the MOTChallenge layout (jointflow/mot_evaluation.hpp): detection recall and
// precision, CLEAR MOT, IDF1 and HOTA as py-motmetrics and TrackEval compute them. PATH is a MOT
// .txt or the product's JSON Lines for one sequence, or a folder of <sequence>.txt / .jsonl.
#include <iostream>

#include <CLI/CLI.hpp>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "jointflow/mot_evaluation.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "PoseTrack evaluation (poseval-compatible): per-joint and total MOTA, MOTP, "
      "precision, recall and mAP; IDF1, IDP and IDR as py-motmetrics computes them"};
  std::string gt_path, mot_gt_path, pred_path;
  jointflow::mot::MotEvalOptions mot_options;
  bool as_json = false;
  bool keep_last_frame = false, count_all_in_empty_frames = false, motp_matches_only = false;
  jointflow::PoseTrackEvalOptions options;
  auto* gt = app.add_option("--gt", gt_path, "ground truth: a PoseTrack file or a folder of them");
  auto* mot_gt = app.add_option("--mot-gt", mot_gt_path,
                                "ground truth boxes: a MOTChallenge sequence folder (gt/gt.txt) "
                                "or a folder of them");
  gt->excludes(mot_gt);
  app.add_option("--pred", pred_path,
                 "predictions: a PoseTrack file or folder (--gt); a MOT .txt or JSON Lines file, "
                 "or a folder of <sequence>.txt/.jsonl (--mot-gt)")
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
  app.add_option("--min-visibility", mot_options.min_visibility,
                 "--mot-gt: pedestrians less visible than this are ignored, as distractors "
                 "(0 = TrackEval's MOT17 rule)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--min-score", mot_options.min_score,
                 "--mot-gt: predictions of lower confidence are dropped")
      ->capture_default_str();
  app.add_option("--iou", mot_options.iou_threshold,
                 "--mot-gt: lowest IoU of a match for CLEAR MOT and IDF1")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (gt_path.empty() && mot_gt_path.empty()) {
    std::cerr << "jointflow-eval: give the ground truth, --gt (PoseTrack) or --mot-gt (MOT)\n";
    return 2;
  }
  if (!mot_gt_path.empty()) {
    try {
      const auto result = jointflow::mot::evaluateFiles(mot_gt_path, pred_path, mot_options);
      std::cout << (as_json ? jointflow::mot::resultJson(result) + "\n"
                            : jointflow::mot::formatTable(result));
    } catch (const jointflow::Error& e) {
      std::cerr << "jointflow-eval: " << e.what() << "\n";
      return 1;
    }
    return 0;
  }
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
