// MOTChallenge box evaluation: how many of the people a camera shows the product finds, and how
// well it keeps their ids, scored as the MOT benchmarks score trackers.
//
// Input: the MOTChallenge layout (a sequence folder with gt/gt.txt, optionally seqinfo.ini and
// img1/; or a folder of such sequences) and predictions as MOT .txt files or the product's JSON
// Lines (jointflow-track --output-json, jointflowjsonwriter).
//
// Preprocessing is TrackEval's for MOT17 (MotChallenge2DBox, do_preproc), with one addition:
//   1. per frame, every ground-truth row (all classes) is matched one-to-one to the predictions by
//      the Hungarian method on IoU (pairs below 0.5 cannot match); predictions matched to a
//      distractor (classes 2 static person, 7 distractor, 8 reflection, 12 person on vehicle)
//      are removed: they are people or things the benchmark neither asks for nor punishes;
//   2. only pedestrians (class 1) with flag 1 are then kept as ground truth.
//   The addition: a pedestrian with flag 1 whose visibility is below `min_visibility` counts as a
//   distractor (step 1 removes the prediction on it; step 2 drops it). 0 gives TrackEval exactly;
//   the default 0.5 scores what a camera user calls "visible people", as the issue measured.
//
// Figures, each equal to its reference implementation on the same preprocessed data
// (tests/eval/test_mot_reference.py checks both):
//   - CLEAR MOT (Bernardin & Stiefelhagen 2008) and identity (IDF1, IDP, IDR; Ristani et al.
//     2016): py-motmetrics 1.4.0's MOTAccumulator (jointflow::MotAccumulator) with distance
//     1 - IoU and pairs at IoU < `iou_threshold` forbidden. Recall and precision are the
//     detection figures of the same matching. MOTP is reported as TrackEval does, the mean IoU
//     of the matches (motmetrics' MOTP is 1 minus it).
//   - HOTA (Luiten et al. 2020) with DetA, AssA, LocA, DetRe, DetPr, AssRe, AssPr: TrackEval's
//     HOTA, the mean over alpha = 0.05, 0.10, ..., 0.95.
// Several sequences combine as the references combine them: CLEAR and identity counts summed
// (motmetrics' OVERALL row), HOTA's counts summed and its association figures weighted by each
// sequence's true positives (TrackEval's combine_sequences).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "jointflow/evaluation.hpp"
#include "jointflow/hota.hpp"

namespace jointflow::mot {

/// One box of a MOT file, x/y the top-left corner, pixels.
struct Box {
  std::int64_t id = -1;
  double x = 0, y = 0, w = 0, h = 0;
  double confidence = 1.0;  ///< predictions: column 7 (or JSON "confidence")
  int flag = 1;             ///< ground truth: column 7, 0 = not to be evaluated
  int cls = 1;              ///< ground truth: column 8, 1 = pedestrian
  double visibility = 1.0;  ///< ground truth: column 9
};

/// Boxes per frame; frames[0] is MOT frame 1.
using Frames = std::vector<std::vector<Box>>;

/// A ground-truth sequence of the MOTChallenge layout.
struct GroundTruthSequence {
  std::string name;  ///< the folder's name, e.g. "MOT17-02-FRCNN"
  Frames frames;     ///< every evaluated frame, also those without people
};

/// The sequences under `path`: the folder itself when it holds gt/gt.txt, else each subfolder
/// (and each subfolder of a `train`/`test` folder) that does, sorted by name. The number of
/// frames is the count of files in img1/ where that folder exists (MOT17-mini keeps a few of the
/// frames its seqinfo.ini counts), else seqinfo.ini's seqLength, else gt.txt's last frame.
/// Throws jointflow::Error when none is found or a file is malformed (naming file and line).
std::vector<GroundTruthSequence> readGroundTruth(const std::string& path);

/// Predictions of one sequence from a MOT .txt file (frame,id,x,y,w,h,conf,...) or the product's
/// JSON Lines (.jsonl / .json: {"frame": 0-based, "objects": [{"id","confidence","x","y","w",
/// "h"}]}). Rows past `num_frames` are ignored; rows whose id is -1 (a detection file such as
/// MOT17's det/det.txt) each get an id of their own. Throws jointflow::Error naming the file and
/// line of anything malformed, a repeated id in a frame, or a box of negative size.
Frames readPredictions(const std::string& file, std::size_t num_frames);

struct MotEvalOptions {
  double iou_threshold = 0.5;   ///< CLEAR and identity: pairs below cannot match (TrackEval 0.5)
  double min_visibility = 0.5;  ///< pedestrians less visible count as distractors; 0 = TrackEval
  double min_score = 0.0;       ///< predictions below this confidence are dropped first
};

struct MotScores {
  std::int64_t frames = 0;
  std::int64_t gt_dets = 0, pred_dets = 0;  ///< boxes after preprocessing
  std::int64_t gt_ids = 0, pred_ids = 0;    ///< distinct ids after preprocessing
  MotAccumulator::Counts clear;             ///< events and identity counts
  double matched_iou = 0.0;                 ///< sum of the IoU of CLEAR's matches (MOTP)
  HotaCounts hota;

  // Percent; NaN where undefined (no ground truth, no predictions).
  double recall() const;
  double precision() const;
  double mota() const;
  double motp() const;
  double idf1() const;
  double idp() const;
  double idr() const;
  HotaScores hotaScores() const { return jointflow::hotaScores(hota); }

  MotScores& operator+=(const MotScores& other);
};

struct MotEvalResult {
  std::vector<std::pair<std::string, MotScores>> sequences;
  MotScores combined;
};

/// Scores one sequence's predictions against its ground truth (frames paired by position; the
/// predictions may have fewer frames, the rest count as empty).
MotScores evaluateSequence(const Frames& ground_truth, const Frames& predictions,
                           const MotEvalOptions& options = {});

/// Reads and scores: `gt_path` as readGroundTruth; `pred_path` a file (one ground-truth sequence)
/// or a folder holding `<sequence>.txt`, `.jsonl` or `.json` for each sequence. Throws
/// jointflow::Error for a sequence without predictions.
MotEvalResult evaluateFiles(const std::string& gt_path, const std::string& pred_path,
                            const MotEvalOptions& options = {});

/// A table per sequence and combined: people and finds per frame, recall, precision, MOTA, MOTP,
/// id switches, IDF1, HOTA, DetA, AssA.
std::string formatTable(const MotEvalResult& result);

/// {"sequences": {name: scores}, "combined": scores}; ratios in percent, NaN as null.
std::string resultJson(const MotEvalResult& result);

/// One line of a MOT results file: frame (1-based), id, x, y, w, h, confidence, -1, -1, -1.
std::string motLine(std::int64_t frame, const Box& box);

}  // namespace jointflow::mot
