// track-quality: the whole pipeline on a PoseTrack-layout folder (images + ground truth), scored
// with the poseval-equivalent evaluation, for every similarity and frame strides 1, 2 and 3 (the
// larger strides stand for faster motion).
//
// The spatial model runs once per frame and its SpatialResults are cached, so every similarity
// sees the same detections and the table compares association alone. The TFF network (similarity
// "tff") runs per stride on the cached maps. Writes a Markdown table (default
// docs/track-quality.md).
//
//   track-quality [--root DIR] [--gt PATH] [--model movenet] [--strides 1,2,3,4]
//                 [--similarities tff,oks,iou,pckh,flow] [--joint-threshold T] [--out FILE]
//                 [--input-size max:640|native|WxH] [--tff-max-grid N]
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tff_model.hpp"

using namespace jointflow;
namespace pt = jointflow::posetrack;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// One frame's cached input: the spatial result, the grey image (for "flow" and the camera
/// motion) and the colour image (re-identification), as the Tracker hands them on.
struct CachedFrame {
  SpatialResult spatial;
  cv::Mat grey;
  cv::Mat bgr;
};

// PoseTrack's videos run at about 25 frames/s; frame f of a sequence is at f / 25 s.
constexpr double kFramesPerSecond = 25.0;

struct CachedSequence {
  pt::Sequence gt;
  std::vector<CachedFrame> frames;
  double spatial_seconds = 0.0;
};

CachedSequence runSpatial(const std::string& gt_file, const std::string& root,
                          SpatialModel& model) {
  CachedSequence seq;
  seq.gt = pt::readSequence(gt_file);
  for (const pt::Frame& frame : seq.gt.frames) {
    const std::string path = (fs::path(root) / frame.file_name).string();
    const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
    if (image.empty())
      throw Error(path + ": cannot read the frame image (named in " + gt_file + ")");
    const auto t0 = Clock::now();
    CachedFrame cached{model.estimate(image), {}, image};
    seq.spatial_seconds += secondsSince(t0);
    cv::cvtColor(image, cached.grey, cv::COLOR_BGR2GRAY);
    seq.frames.push_back(std::move(cached));
  }
  return seq;
}

/// The ground truth and the frame indices kept at a stride.
std::vector<std::size_t> strideFrames(std::size_t n, int stride) {
  std::vector<std::size_t> idx;
  for (std::size_t f = 0; f < n; f += static_cast<std::size_t>(stride)) idx.push_back(f);
  return idx;
}

struct RunResult {
  pt::Sequence predictions;
  double association_seconds = 0.0;
  double tff_seconds = 0.0;
  int frames = 0;
};

RunResult track(const CachedSequence& seq, const std::vector<std::size_t>& idx,
                const TrackerSettings& settings, TemporalFlowModel* tff, float joint_threshold) {
  RunResult run;
  run.predictions = seq.gt;
  run.predictions.frames.clear();
  PoseAssociator associator(settings);
  if (tff) tff->reset();
  pt::TrackIdMap ids;
  for (std::size_t f : idx) {
    const CachedFrame& cached = seq.frames[f];
    cv::Mat flow_field;
    if (tff) {
      const auto t0 = Clock::now();
      flow_field = tff->predict(cached.spatial.features, cached.spatial.beliefs);
      run.tff_seconds += secondsSince(t0);
    }
    const auto t0 = Clock::now();
    AssociationFrame in;
    in.poses = cached.spatial.poses;
    in.tff = flow_field;
    in.grid_to_frame = cached.spatial.grid_to_frame;
    in.features = cached.spatial.features;
    in.grey = cached.grey;
    in.bgr = cached.bgr;
    in.time = static_cast<double>(f) / kFramesPerSecond;  // strides skip frames: gaps in time
    const std::vector<TrackedPose> tracked = associator.update(in);
    run.association_seconds += secondsSince(t0);
    ++run.frames;

    pt::Frame frame = seq.gt.frames[f];
    frame.people.clear();
    std::vector<std::int64_t> tracker_ids;
    for (const TrackedPose& t : tracked) tracker_ids.push_back(t.track_id);
    const std::vector<int> numbers = ids.assign(tracker_ids);
    for (std::size_t k = 0; k < tracked.size(); ++k) {
      pt::Person person;
      person.track_id = numbers[k];
      person.score = tracked[k].pose.score;
      person.joints = pt::toPoseTrackJoints(tracked[k].pose, joint_threshold);
      frame.people.push_back(std::move(person));
    }
    run.predictions.frames.push_back(std::move(frame));
  }
  return run;
}

pt::Sequence strideGroundTruth(const pt::Sequence& gt, const std::vector<std::size_t>& idx) {
  pt::Sequence out = gt;
  out.frames.clear();
  for (std::size_t f : idx) out.frames.push_back(gt.frames[f]);
  return out;
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Tracking quality of every similarity on a PoseTrack-layout folder"};
  std::string root = std::string(JOINTFLOW_DEFAULT_DATA_DIR) + "/bonn-posetrack";
  std::string gt_path;
  std::string model_type = "movenet", tff_path, out_path = "docs/track-quality.md";
  std::string strides_text = "1,2,3,4", similarities_text = "tff,oks,iou,pckh,flow";
  std::string input_size;
  int tff_max_grid = 0;
  std::string matcher = "greedy";
  float joint_threshold = 0.3f;
  app.add_option("--root", root, "PoseTrack-layout folder: frame paths are relative to it")
      ->capture_default_str();
  app.add_option("--gt", gt_path, "ground-truth file or folder (default ROOT/annotations/test)");
  app.add_option("--model", model_type, "spatial model: movenet | posenet")->capture_default_str();
  app.add_option("--tff-model", tff_path, "TFF ONNX file (default models/tff_<model>.onnx)");
  app.add_option("--strides", strides_text, "frame strides")->capture_default_str();
  app.add_option("--similarities", similarities_text, "similarities")->capture_default_str();
  app.add_option("--matcher", matcher, "greedy | optimal")->capture_default_str();
  app.add_option("--joint-threshold", joint_threshold,
                 "joints scoring below are not written (poseval counts every written joint)")
      ->capture_default_str();
  app.add_option("--out", out_path, "Markdown file to write")->capture_default_str();
  app.add_option("--input-size", input_size,
                 "spatial model input size policy (default: SpatialOptions' max:640)");
  app.add_option("--tff-max-grid", tff_max_grid,
                 "TFF network grid limit (TemporalFlowModel max_grid_side; 0 = never resample)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  root = fs::weakly_canonical(root).string();
  if (gt_path.empty()) gt_path = root + "/annotations/test";

  try {
    SpatialOptions spatial_options;
    if (!input_size.empty()) spatial_options.input_size = InputSize::parse(input_size);
    auto model = createSpatialModel(parseEnum<ModelType>(model_type), spatial_options);
    if (tff_path.empty())
      tff_path = defaultModelsDir() + "/tff_" + toString(model->type()) + ".onnx";

    std::vector<CachedSequence> sequences;
    double spatial_seconds = 0.0;
    int spatial_frames = 0;
    for (const std::string& file : pt::listSequenceFiles(gt_path)) {
      sequences.push_back(runSpatial(file, root, *model));
      spatial_seconds += sequences.back().spatial_seconds;
      spatial_frames += static_cast<int>(sequences.back().frames.size());
      std::cerr << "spatial model done: " << file << "\n";
    }

    std::unique_ptr<TemporalFlowModel> tff;
    std::string tff_note;
    if (fs::exists(tff_path)) {
      tff = std::make_unique<TemporalFlowModel>(tff_path, model->featureChannels(), DnnOptions{},
                                                tff_max_grid);
    } else {
      tff_note = "no TFF model at " + tff_path;
    }

    std::ostringstream table;
    table << "| stride | similarity | MOTA | MOTP | precision | recall | mAP | id switches | "
             "association frames/s | pipeline frames/s |\n"
          << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::ostringstream skipped;
    for (const std::string& stride_text : split(strides_text)) {
      const int stride = std::stoi(stride_text);
      for (const std::string& similarity : split(similarities_text)) {
        if (similarity == "tff" && !tff) {
          skipped << "- stride " << stride << ", tff: not run (" << tff_note << ")\n";
          continue;
        }
        TrackerSettings settings;
        settings.similarity = parseEnum<SimilarityType>(similarity);
        settings.matcher = parseEnum<Matcher>(matcher);
        std::vector<pt::Sequence> gts, preds;
        double assoc = 0.0, tff_time = 0.0, spatial_share = 0.0;
        int frames = 0;
        for (const CachedSequence& seq : sequences) {
          const auto idx = strideFrames(seq.frames.size(), stride);
          RunResult run =
              track(seq, idx, settings, similarity == "tff" ? tff.get() : nullptr, joint_threshold);
          assoc += run.association_seconds;
          tff_time += run.tff_seconds;
          frames += run.frames;
          spatial_share += seq.spatial_seconds * idx.size() / seq.frames.size();
          gts.push_back(strideGroundTruth(seq.gt, idx));
          preds.push_back(std::move(run.predictions));
        }
        const PoseTrackEvalResult r = evaluatePoseTrack(gts, preds);
        table << std::fixed << std::setprecision(1) << "| " << stride << " | " << similarity
              << " | " << r.total.mota << " | " << r.total.motp << " | " << r.total.precision
              << " | " << r.total.recall << " | " << r.total.ap << " | " << r.total.counts.switches
              << " | " << std::setprecision(0) << frames / assoc << " | " << std::setprecision(1)
              << frames / (spatial_share + tff_time + assoc) << " |\n";
        std::cerr << "stride " << stride << " " << similarity << " done\n";
      }
    }

    std::ostringstream doc;
    doc << "# Tracking quality per similarity\n\n"
        << "Written by `bench/track_quality` (build/bench/track-quality); regenerate with\n\n"
        << "    build/bench/track-quality --root " << root << " --model " << model_type
        << " --strides " << strides_text << " --similarities " << similarities_text << " --matcher "
        << matcher << " --joint-threshold " << joint_threshold
        << (input_size.empty() ? "" : " --input-size " + input_size)
        << (tff_max_grid == 0 ? "" : " --tff-max-grid " + std::to_string(tff_max_grid)) << "\n\n"
        << "Ground truth: `" << gt_path << "` (" << sequences.size() << " sequence(s), "
        << spatial_frames << " frames). Spatial model: " << toString(model->type())
        << " (input size " << (input_size.empty() ? std::string("default") : input_size)
        << "), run once per frame; every similarity associates the same cached "
           "detections with the default TrackerSettings (matcher "
        << matcher << "). Joints scoring below " << joint_threshold
        << " are not written. A stride of s keeps every s-th frame (ground truth and "
           "predictions alike), standing for s times faster motion.\n\n"
        << "Metrics: poseval-equivalent (jointflow-eval defaults, quirks included): MOTA, MOTP, "
           "precision, recall and mAP in percent, means over joints; id switches summed over "
           "joints. Association frames/s times PoseAssociator::update (plus the TFF network for "
           "tff); pipeline frames/s adds the spatial model ("
        << std::fixed << std::setprecision(1) << spatial_frames / spatial_seconds
        << " frames/s here). Timings from one run on this machine, single stream.\n\n"
        << table.str();
    if (!skipped.str().empty()) doc << "\nNot run:\n\n" << skipped.str();

    fs::create_directories(fs::path(out_path).parent_path().empty()
                               ? fs::path(".")
                               : fs::path(out_path).parent_path());
    std::ofstream out(out_path);
    if (!out) throw Error(out_path + ": cannot write the table");
    out << doc.str();
    std::cout << doc.str();
  } catch (const Error& e) {
    std::cerr << "track-quality: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
