#include "live_cases.hpp"

#include <gst/gst.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "cached_tracking.hpp"
#include "ground_truth_ids.hpp"
#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "live_pipeline.hpp"
#include "text_format.hpp"
#include "variants.hpp"

namespace jointflow::bench {
namespace {

namespace fs = std::filesystem;
namespace pt = jointflow::posetrack;
using json = nlohmann::json;

bool elementFound() {
  GstElementFactory* factory = gst_element_factory_find("jointflowtrack");
  if (factory) gst_object_unref(factory);
  return factory != nullptr;
}

constexpr const char* kNoElement =
    "Not run: the jointflowtrack element is not found (set GST_PLUGIN_PATH to build/gst-plugin; "
    "`make bench-identity` does).\n";

/// `launch` as a user would type it: the scratch folder's files (`paths`) by their names alone.
std::string typed(std::string launch, const std::vector<fs::path>& paths) {
  for (const fs::path& p : paths) {
    const std::string path = p.string();
    const size_t at = launch.find(path);
    if (at != std::string::npos) launch.replace(at, path.size(), p.filename().string());
  }
  return launch;
}

// ---- vtest.avi: ids
// ------------------------------------------------------------------------------

json idCounts(const PipelineRun& run) {
  std::set<std::int64_t> ids, confirmed;
  for (const auto& frame : run.frames)
    for (const TrackedPose& p : frame) {
      ids.insert(p.track_id);
      if (!p.tentative) confirmed.insert(p.track_id);
    }
  return {{"ran", run.ran},
          {"note", run.note},
          {"frames", static_cast<int>(run.frames.size())},
          {"ids", static_cast<int>(ids.size())},
          {"confirmed", static_cast<int>(confirmed.size())},
          {"seconds", run.seconds}};
}

// ---- Bonn: scores
// --------------------------------------------------------------------------------

/// The ground truth of the frames that reached the tracker (frame k of the clip at k / fps s) and
/// the tracks written on them, scored as the other Bonn cases are.
json score(const pt::Sequence& gt, const PipelineRun& run, double fps, float joint_threshold) {
  pt::Sequence reached = gt;
  reached.frames.clear();
  TrackRun tracks;
  int last = -1;
  for (size_t i = 0; i < run.frames.size(); ++i) {
    // (lround of NaN is unspecified: a buffer without a timestamp gets -1, which fails below.)
    const int k = std::isnan(run.times[i]) ? -1 : static_cast<int>(std::lround(run.times[i] * fps));
    if (k <= last || k >= static_cast<int>(gt.frames.size()))
      throw Error("live Bonn case: buffer " + std::to_string(i) + " at " + fixed(run.times[i], 3) +
                  " s is not a frame of the clip after frame " + std::to_string(last));
    reached.frames.push_back(gt.frames[static_cast<size_t>(k)]);
    tracks.frames.push_back(run.frames[i]);
    last = k;
  }
  const pt::Sequence pred = predictionSequence(reached, tracks, joint_threshold);
  json total = json::parse(poseTrackResultJson(evaluatePoseTrack({reached}, {pred})))["total"];
  total["id_switches_ground_truth_ids"] = groundTruthIdSwitches({reached}, {pred});
  total["frames"] = static_cast<int>(reached.frames.size());
  total["seconds"] = run.seconds;
  return total;
}

/// "MOTA / joint id switches [the same poses with the ground truth's ids] / IDF1", as the other
/// Bonn cases' cells.
std::string cell(const json& total) {
  auto num = [](const json& v, int d) {
    return v.is_null() ? std::string("n/a") : fixed(v.get<double>(), d);
  };
  std::ostringstream s;
  s << num(total["mota"], 1) << " / " << total["id_switches"] << " ["
    << total["id_switches_ground_truth_ids"] << "] / " << num(total["idf1"], 1);
  return s.str();
}

std::string engineName(const std::string& backend) {
  return backend == "openvino" ? "OpenVINO" : backend == "opencv" ? "cv::dnn" : backend;
}

}  // namespace

LiveCase liveVtest(const std::string& vtest, int frames, const std::string& scratch,
                   const Log& log) {
  LiveCase out;
  if (!elementFound()) {
    out.markdown = kNoElement;
    return out;
  }
  fs::create_directories(scratch);
  const std::string source =
      "filesrc location=\"" + vtest +
      "\" ! decodebin ! videoconvert ! identity eos-after=" + std::to_string(frames);
  const fs::path live_json = fs::path(scratch) / "live.jsonl";
  const fs::path offline_json = fs::path(scratch) / "offline.jsonl";
  const std::string live_launch = trackPipeline(source, true, "", live_json.string());
  const std::string offline_launch = trackPipeline(source, false, "", offline_json.string());
  log("live pipeline, " + std::to_string(frames) + " frames in real time");
  const json live = idCounts(runPipeline(live_launch, live_json.string()));
  log("offline pipeline");
  const json offline = idCounts(runPipeline(offline_launch, offline_json.string()));
  fs::remove_all(scratch);
  out.figures = {{"live", live},
                 {"offline", offline},
                 {"live_launch", typed(live_launch, {live_json})},
                 {"offline_launch", typed(offline_launch, {offline_json})}};
  std::ostringstream md;
  md << "| run | frames that reached jointflowtrack | distinct ids | confirmed | seconds |\n"
     << "|---|---:|---:|---:|---:|\n";
  for (const char* name : {"live", "offline"}) {
    const json& p = out.figures[name];
    if (!p["ran"].get<bool>()) {
      md << "| " << name << " | not run: " << p["note"].get<std::string>() << " | | | |\n";
      continue;
    }
    md << "| " << name << " | " << p["frames"] << " | " << p["ids"] << " | " << p["confirmed"]
       << " | " << fixed(p["seconds"].get<double>(), 0) << " |\n";
  }
  md << "\nlive:\n\n    gst-launch-1.0 " << typed(live_launch, {live_json})
     << "\n\noffline:\n\n    gst-launch-1.0 " << typed(offline_launch, {offline_json}) << "\n";
  out.markdown = md.str();
  return out;
}

LiveCase liveBonn(const std::vector<cv::Mat>& images, const pt::Sequence& source,
                  const LiveBonnOptions& options, const std::string& scratch, const Log& log) {
  LiveCase out;
  if (!elementFound()) {
    out.markdown = kNoElement;
    return out;
  }
  fs::create_directories(scratch);
  // The clip: forward-backward play, frame k at k / fps, with its ground truth.
  Variant clip{"live-bonn", "", images.front().size(), {}};
  std::vector<cv::Mat> frames;
  for (int f : pingPongTimeline(static_cast<int>(images.size()), options.frames)) {
    clip.frames.push_back(FrameRecipe{f});
    frames.push_back(images[static_cast<size_t>(f)]);
  }
  const pt::Sequence gt = variantGroundTruth(source, clip);
  const fs::path clip_path = fs::path(scratch) / "bonn.avi";
  writeClip(frames, options.fps, clip_path.string());
  const std::string head = "filesrc location=\"" + clip_path.string() + "\" ! decodebin";
  const fs::path jsonl = fs::path(scratch) / "tracks.jsonl";

  std::ostringstream md;
  md << "| engine | similarity | offline, all " << options.frames
     << " frames | live: frames that reached the tracker | live |\n|---|---|---|---:|---|\n";
  json rows = json::array();
  std::string example_live, example_offline;
  for (const std::string& backend : options.backends) {
    for (const std::string& similarity : options.similarities) {
      const std::string properties = "backend=" + backend + " similarity=" + similarity +
                                     (options.properties.empty() ? "" : " " + options.properties);
      json row = {{"backend", backend}, {"similarity", similarity}};
      std::string cells[3];
      bool ran = true;
      for (const bool live : {false, true}) {
        const std::string launch = trackPipeline(head, live, properties, jsonl.string());
        (live ? example_live : example_offline) = typed(launch, {clip_path, jsonl});
        log("  live-bonn: " + backend + ", " + similarity + (live ? ", live" : ", offline"));
        const PipelineRun run = runPipeline(launch, jsonl.string());
        fs::remove(jsonl);
        if (!run.ran) {
          row["note"] = run.note;
          ran = false;
          break;
        }
        const json total = score(gt, run, options.fps, options.joint_threshold);
        row[live ? "live" : "offline"] = total;
        if (live) {
          cells[1] = std::to_string(total["frames"].get<int>());
          cells[2] = cell(total);
        } else {
          cells[0] = cell(total);
        }
      }
      rows.push_back(row);
      if (!ran) {
        md << "| " << engineName(backend) << " | " << similarity
           << " | not run: " << row["note"].get<std::string>() << " | | |\n";
        continue;
      }
      md << "| " << engineName(backend) << " | " << similarity << " | " << cells[0] << " | "
         << cells[1] << " | " << cells[2] << " |\n";
    }
  }
  fs::remove_all(scratch);
  out.figures = {{"frames", options.frames},
                 {"fps", options.fps},
                 {"runs", rows},
                 {"live_launch", example_live},
                 {"offline_launch", example_offline}};
  md << "\nThe last live line run (bonn.avi: the clip this benchmark writes):\n\n    "
        "gst-launch-1.0 "
     << example_live << "\n";
  out.markdown = md.str();
  return out;
}

}  // namespace jointflow::bench
