// track-quality: the whole pipeline on a PoseTrack-layout folder (images + ground truth), scored
// with the poseval-equivalent evaluation, for every similarity and frame strides 1 to 4 (the
// larger strides stand for faster motion), at the spatial model's default input size or another.
//
// The spatial model runs once per frame and its SpatialResults are cached, so every similarity
// sees the same detections and the table compares association alone; each similarity's
// jointflow::Tracker continues from the cached result (bench/cached_tracking.hpp), TFF network
// included. Writes a Markdown table (default docs/track-quality.md).
//
//   track-quality [--root DIR] [--gt PATH] [--model movenet] [--strides 1,2,3,4]
//                 [--similarities auto,tff,oks,iou,pckh,flow] [--joint-threshold T] [--out FILE]
//                 [--input-size max:640|native|WxH] [--predictions DIR]
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "association_options.hpp"
#include "cached_tracking.hpp"
#include "ground_truth_ids.hpp"
#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/spatial_model.hpp"
#include "setting_args.hpp"
#include "variants.hpp"

using namespace jointflow;
namespace pt = jointflow::posetrack;
namespace fs = std::filesystem;

namespace {

struct CachedSequence {
  pt::Sequence gt;
  std::vector<bench::CachedFrame> frames;
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
    seq.frames.push_back(bench::estimateFrame(model, image));
    seq.spatial_seconds += seq.frames.back().spatial_seconds;
  }
  return seq;
}

pt::Sequence strideGroundTruth(const pt::Sequence& gt, const std::vector<int>& idx) {
  pt::Sequence out = gt;
  out.frames.clear();
  for (int f : idx) out.frames.push_back(gt.frames[f]);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Tracking quality of every similarity on a PoseTrack-layout folder"};
  std::string root = std::string(JOINTFLOW_DEFAULT_DATA_DIR) + "/bonn-posetrack";
  std::string gt_path;
  std::string model_type = "movenet", out_path = "docs/track-quality.md";
  std::string strides_text = "1,2,3,4", similarities_text = "auto,tff,oks,iou,pckh,flow";
  std::string matcher = "greedy", input_size;
  float joint_threshold = 0.3f;
  app.add_option("--root", root, "PoseTrack-layout folder: frame paths are relative to it")
      ->capture_default_str();
  app.add_option("--gt", gt_path, "ground-truth file or folder (default ROOT/annotations/test)");
  app.add_option("--model", model_type, "spatial model: movenet | posenet")->capture_default_str();
  app.add_option("--strides", strides_text, "frame strides")->capture_default_str();
  app.add_option("--similarities", similarities_text, "similarities")->capture_default_str();
  app.add_option("--matcher", matcher, "greedy | optimal")->capture_default_str();
  app.add_option("--joint-threshold", joint_threshold,
                 "joints scoring below are not written (poseval counts every written joint)")
      ->capture_default_str();
  app.add_option("--out", out_path, "Markdown file to write")->capture_default_str();
  std::string predictions_dir;
  app.add_option("--predictions", predictions_dir,
                 "folder to write each stride's ground truth and each similarity's tracks to, in "
                 "PoseTrack 2018 form (DIR/sN/SEQUENCE/gt.json, DIR/sN/SEQUENCE/SIMILARITY.json), "
                 "for jointflow-eval or a look at where ids switch");
  app.add_option("--input-size", input_size,
                 "the spatial model's input size policy (default: SpatialOptions', max:640)");
  std::vector<std::string> assignments;
  bench::addSetOption(app, assignments);
  bench::AssociationOptions association;
  association.addTo(app);
  CLI11_PARSE(app, argc, argv);
  root = fs::weakly_canonical(root).string();
  if (gt_path.empty()) gt_path = root + "/annotations/test";

  try {
    TrackerSettings configured;
    bench::applySettings(configured, assignments);
    SpatialOptions spatial_options = configured.spatial;
    if (!input_size.empty()) spatial_options.input_size = InputSize::parse(input_size);
    // The engine too: `--set backend=openvino` is for both networks, as on jointflow-track.
    auto model =
        createSpatialModel(parseEnum<ModelType>(model_type), spatial_options, configured.engine);
    const std::string tff_path =
        association.tff_model.empty()
            ? defaultModelsDir() + "/tff_" + toString(model->type()) + ".onnx"
            : association.tff_model;

    std::vector<CachedSequence> sequences;
    double spatial_seconds = 0.0;
    int spatial_frames = 0;
    for (const std::string& file : pt::listSequenceFiles(gt_path)) {
      sequences.push_back(runSpatial(file, root, *model));
      spatial_seconds += sequences.back().spatial_seconds;
      spatial_frames += static_cast<int>(sequences.back().frames.size());
      std::cerr << "spatial model done: " << file << "\n";
    }

    std::vector<std::string> similarities;
    std::ostringstream skipped;
    for (const std::string& similarity : bench::splitList(similarities_text)) {
      if (similarity == "tff" && !fs::exists(tff_path)) {
        skipped << "- tff: not run (no TFF model at " << tff_path << ")\n";
        continue;
      }
      similarities.push_back(similarity);
    }
    TrackerSettings base = configured;
    base.model_type = model->type();
    base.spatial = spatial_options;
    base.tff_model = tff_path;
    base.matcher = parseEnum<Matcher>(matcher);
    association.applyTo(base);
    bench::SimilarityTrackers trackers(similarities, base);

    // rows[stride][similarity]
    std::map<int, std::map<std::string, std::string>> rows;
    for (const std::string& stride_text : bench::splitList(strides_text)) {
      const int stride = std::stoi(stride_text);
      std::map<std::string, std::vector<pt::Sequence>> preds;
      std::map<std::string, double> seconds;
      std::vector<pt::Sequence> gts;
      double spatial_share = 0.0;
      int frames = 0;
      for (const CachedSequence& seq : sequences) {
        const std::vector<int> idx =
            bench::stridedTimeline(static_cast<int>(seq.frames.size()), stride);
        const pt::Sequence gt = strideGroundTruth(seq.gt, idx);
        // Kept frames follow each other at the default frame rate: a stride is faster motion.
        const auto runs = trackers.run(
            static_cast<int>(idx.size()),
            [&](int k) -> const bench::CachedFrame& { return seq.frames[idx[k]]; },
            [&](int k) { return k / static_cast<double>(base.frame_rate); });
        const fs::path dir =
            fs::path(predictions_dir) / ("s" + std::to_string(stride)) / seq.gt.name;
        if (!predictions_dir.empty()) {
          fs::create_directories(dir);
          pt::writeSequence(gt, (dir / "gt.json").string(), pt::Format::k2018);
        }
        for (const bench::TrackRun& run : runs) {
          preds[run.similarity].push_back(bench::predictionSequence(gt, run, joint_threshold));
          if (!predictions_dir.empty())
            pt::writeSequence(preds[run.similarity].back(),
                              (dir / (run.similarity + ".json")).string(), pt::Format::k2018);
          seconds[run.similarity] += run.seconds;
        }
        frames += static_cast<int>(idx.size());
        spatial_share += seq.spatial_seconds * idx.size() / seq.frames.size();
        gts.push_back(gt);
      }
      for (const std::string& similarity : similarities) {
        const PoseTrackEvalResult r = evaluatePoseTrack(gts, preds[similarity]);
        // The same poses with the ground truth's ids: the switches association did not make.
        const auto floor = bench::groundTruthIdSwitches(gts, preds[similarity]);
        const double assoc = seconds[similarity];
        std::ostringstream row;
        row << std::fixed << std::setprecision(1) << "| " << stride << " | " << similarity << " | "
            << r.total.mota << " | " << r.total.motp << " | " << r.total.precision << " | "
            << r.total.recall << " | " << r.total.ap << " | " << r.total.counts.switches << " | "
            << floor << " | " << r.total.idf1 << " | " << std::setprecision(0) << frames / assoc
            << " | " << std::setprecision(1) << frames / (spatial_share + assoc) << " |\n";
        rows[stride][similarity] = row.str();
      }
      std::cerr << "stride " << stride << " done\n";
    }
    std::ostringstream table;
    table << "| stride | similarity | MOTA | MOTP | precision | recall | mAP | id switches | id "
             "switches, ground-truth ids | IDF1 | association frames/s | pipeline frames/s |\n"
          << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& [stride, by_similarity] : rows)
      for (const std::string& similarity : similarities) table << by_similarity.at(similarity);

    std::ostringstream doc;
    doc << "# Tracking quality per similarity\n\n"
        << "Written by `bench/track_quality` (build/bench/track-quality); regenerate with\n\n"
        << "    build/bench/track-quality --root " << root << " --model " << model_type
        << " --strides " << strides_text << " --similarities " << similarities_text << " --matcher "
        << matcher << " --joint-threshold " << joint_threshold << " " << association.commandLine()
        << (input_size.empty() ? "" : " --input-size " + input_size);
    doc << bench::setArguments(assignments);
    doc << "\n\n"
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
           "joints; IDF1 from the identity counts summed over joints. Association frames/s times "
           "Tracker::process after the spatial model (the TFF network included for tff); "
           "pipeline frames/s adds the spatial model ("
        << std::fixed << std::setprecision(1) << spatial_frames / spatial_seconds
        << " frames/s here). Timings from one run on this machine, single stream. Id switches, "
           "ground-truth ids: the same poses with each pose given the id of the annotated person "
           "it holds the most joints of (bench/ground_truth_ids.hpp), what a tracker that always "
           "knew who is who would make with them; those come from the poses (one holding or "
           "lying near joints of two people, two on one person), the rest from association.\n\n"
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
