// identity-bench's cases (identity_cases.hpp); what each measures is in bench/identity.cpp's
// file comment, the prose around their figures in identity_document.cpp.
#include "identity_cases.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "assoc_sim.hpp"
#include "camera_accuracy.hpp"
#include "ground_truth_ids.hpp"
#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "markdown_table.hpp"
#include "text_format.hpp"
#include "visit_sheet.hpp"

namespace jointflow::bench {
namespace {

namespace pt = jointflow::posetrack;
namespace fs = std::filesystem;
using json = nlohmann::json;

/// The "total" object of jointflow-eval --json (every figure and count).
json totalJson(const PoseTrackEvalResult& r) {
  return json::parse(poseTrackResultJson(r))["total"];
}

int distinctIds(const TrackRun& run) {
  std::set<std::int64_t> ids;
  for (const auto& frame : run.frames)
    for (const TrackedPose& p : frame) ids.insert(p.track_id);
  return static_cast<int>(ids.size());
}

/// The occluder's measure: of the hidden episodes whose person is matched to a predicted id
/// before and after, how many come back under the same id.
struct ReturnCount {
  int episodes = 0;             ///< hidden episodes (the person visible before and after)
  int seen = 0;                 ///< with the person matched before and after the episode
  int same = 0;                 ///< of those, back under the same id
  json detail = json::array();  ///< per episode counted: the person, frames, ids before and after
};

ReturnCount countReturns(const std::vector<HiddenEpisode>& episodes, const pt::Sequence& gt,
                         const pt::Sequence& pred, int max_frames) {
  std::vector<std::map<std::int64_t, std::int64_t>> ids;
  for (size_t f = 0; f < gt.frames.size(); ++f)
    ids.push_back(personIds(gt.frames[f], pred.frames[f]));
  ReturnCount c;
  for (const HiddenEpisode& e : episodes) {
    if (e.frames() > max_frames) continue;
    ++c.episodes;
    std::optional<std::int64_t> before, after;
    for (int f = e.first - 1; f >= 0 && !before; --f) {
      auto it = ids[f].find(e.track_id);
      if (it != ids[f].end()) before = it->second;
    }
    for (int f = e.last + 1; f < static_cast<int>(ids.size()) && !after; ++f) {
      auto it = ids[f].find(e.track_id);
      if (it != ids[f].end()) after = it->second;
    }
    c.detail.push_back({{"track_id", e.track_id},
                        {"first", e.first},
                        {"last", e.last},
                        {"before", before ? json(*before) : json()},
                        {"after", after ? json(*after) : json()}});
    if (!before || !after) continue;
    ++c.seen;
    c.same += *before == *after ? 1 : 0;
  }
  return c;
}

// ---- 4. Live pipeline against the offline run (vtest.avi) ----

void runLiveVtest(IdentityRun& run, IdentityFigures& out) {
  const IdentityOptions& o = run.options;
  if (!fs::exists(o.vtest)) return;
  out.live_vtest = liveVtest(o.vtest, o.live_frames, (run.scratch / "vtest").string(), run.log);
}

// ---- 1. Bonn test sequence variants ----

/// The source frame as it is, from the spatial model's run over all of them (made on first use).
const CachedFrame& stillFrame(IdentityRun& run, int f) {
  BonnSequence& bonn = *run.bonn;
  if (bonn.still.empty()) {
    run.log("spatial model on the " + std::to_string(bonn.images.size()) + " source frames");
    for (const cv::Mat& image : bonn.images) bonn.still.push_back(estimateFrame(*run.model, image));
  }
  return bonn.still[static_cast<size_t>(f)];
}

/// One variant, every similarity: its rows; for the occluder also who comes back under which id.
void runVariant(IdentityRun& run, IdentityFigures& out, const Variant& v) {
  const IdentityOptions& o = run.options;
  const BonnSequence& bonn = *run.bonn;
  const pt::Sequence gt = variantGroundTruth(bonn.source, v);
  const int n = static_cast<int>(v.frames.size());
  run.log("case " + v.name + ": " + std::to_string(n) + " frames");
  CachedFrame current;
  double spatial_seconds = 0.0;
  const auto runs = run.trackers->run(
      n,
      [&](int k) -> const CachedFrame& {
        const FrameRecipe& r = v.frames[static_cast<size_t>(k)];
        if (r.warp == cv::Matx23d(1, 0, 0, 0, 1, 0) && !r.hasOccluder() && v.size == bonn.size)
          return stillFrame(run, r.source);
        current = estimateFrame(*run.model, renderFrame(bonn.images[r.source], r, v.size));
        spatial_seconds += current.spatial_seconds;
        return current;
      },
      [&](int k) { return v.frames[static_cast<size_t>(k)].time; },
      [&](int k) {
        if ((k + 1) % 50 == 0) run.log("  " + v.name + ": frame " + std::to_string(k + 1));
      });
  out.variants_md +=
      "- `" + v.name + "` (" + std::to_string(n) + " frames): " + v.description + "\n";
  const std::vector<HiddenEpisode> episodes =
      v.name == "occluder" ? hiddenEpisodes(bonn.source.frames, v) : std::vector<HiddenEpisode>{};
  const std::string case_dir = o.predictions_dir + "/" + v.name;
  if (!o.predictions_dir.empty()) {
    fs::create_directories(case_dir);
    pt::writeSequence(gt, case_dir + "/gt.json", pt::Format::k2018);
  }
  for (const TrackRun& tracks : runs) {
    const pt::Sequence pred = predictionSequence(gt, tracks, o.joint_threshold);
    if (!o.predictions_dir.empty())
      pt::writeSequence(pred, case_dir + "/" + tracks.similarity + ".json", pt::Format::k2018);
    const PoseTrackEvalResult r = evaluatePoseTrack({gt}, {pred});
    CaseRow row{v.name, tracks.similarity, totalJson(r), n, distinctIds(tracks)};
    row.total["distinct_ids"] = row.ids;
    // The same poses with the ground truth's ids: the switches association did not make.
    row.total["id_switches_ground_truth_ids"] = groundTruthIdSwitches({gt}, {pred});
    row.total["person_id_switches"] = personIdSwitches(gt, pred);
    row.total["person_id_switches_ground_truth_ids"] =
        personIdSwitches(gt, withGroundTruthIds(gt, pred));
    row.total["tracker_seconds"] = tracks.seconds;
    out.rows.push_back(row);
    if (!episodes.empty()) {
      const int limit = static_cast<int>(std::lround(2.0 * o.variant.fps));
      const ReturnCount all = countReturns(episodes, gt, pred, n);
      const ReturnCount upto2 = countReturns(episodes, gt, pred, limit);
      out.occluder[tracks.similarity] = {
          {"episodes", all.episodes},   {"seen_before_and_after", all.seen},
          {"same_id", all.same},        {"episodes_upto_2s", upto2.episodes},
          {"seen_upto_2s", upto2.seen}, {"same_id_upto_2s", upto2.same},
          {"returns", all.detail}};
    }
  }
  if (!episodes.empty()) {
    std::vector<int> lengths;
    for (const HiddenEpisode& e : episodes) lengths.push_back(e.frames());
    std::sort(lengths.begin(), lengths.end());
    json list = json::array();
    for (const HiddenEpisode& e : episodes)
      list.push_back({{"track_id", e.track_id}, {"first", e.first}, {"last", e.last}});
    out.occluder["hidden_episodes"] = list;
    out.occluder_md += "The bar hides a person completely " + std::to_string(episodes.size()) +
                       " times (visible before and after); hidden for " +
                       std::to_string(lengths.front()) + " to " + std::to_string(lengths.back()) +
                       " frames, median " + std::to_string(lengths[lengths.size() / 2]) + " (" +
                       fixed(lengths.front() / o.variant.fps, 1) + " to " +
                       fixed(lengths.back() / o.variant.fps, 1) + " s at " +
                       fixed(o.variant.fps, 0) + " frames/s).\n\n";
  }
  run.log("  " + v.name + " done (spatial model " + fixed(spatial_seconds, 0) + " s)");
}

// ---- 4. The Bonn sequence as a live camera ----

void runLiveBonn(IdentityRun& run, IdentityFigures& out) {
  run.log("the Bonn sequence as a live camera");
  out.live_bonn = liveBonn(run.bonn->images, run.bonn->source, run.options.live_bonn,
                           (run.scratch / "bonn").string(), run.log);
}

// ---- 1. The camera motion estimate against the variants' exact motion ----

void runCamera(IdentityRun& run, IdentityFigures& out) {
  const BonnSequence& bonn = *run.bonn;
  run.log("camera motion estimate against the exact camera motion");
  MarkdownTable table({{"case"},
                       {"frames", true},
                       {"error median", true},
                       {"95th percentile", true},
                       {"max", true},
                       {"frames over 5 px", true},
                       {"estimate, median CPU ms", true}});
  for (const Variant& v : bonn.variants) {
    if (v.name != "still-s1" && v.name != "dropped" && v.name != "shake" && v.name != "pan" &&
        v.name != "zoom" && v.name != "occluder")
      continue;
    const CameraAccuracy a =
        measureCameraEstimate(bonn.images, variantGroundTruth(bonn.source, v), v);
    std::vector<double> e = a.error_px, ms = a.update_ms;
    std::sort(e.begin(), e.end());
    std::sort(ms.begin(), ms.end());
    const double e50 = e[e.size() / 2], e95 = e[std::min(e.size() - 1, e.size() * 95 / 100)];
    const double ms50 = ms[ms.size() / 2];
    const int over =
        static_cast<int>(std::count_if(e.begin(), e.end(), [](double x) { return x > 5.0; }));
    out.camera[v.name] = {{"frames", static_cast<int>(e.size())},
                          {"error_median_px", e50},
                          {"error_p95_px", e95},
                          {"error_max_px", e.back()},
                          {"frames_over_5px", over},
                          {"update_ms", ms50},
                          {"error_px", a.error_px}};
    table.row({v.name, std::to_string(e.size()), fixed(e50, 2) + " px", fixed(e95, 2) + " px",
               fixed(e.back(), 1) + " px", std::to_string(over), fixed(ms50, 2)});
  }
  out.camera_md = table.str();
}

// ---- 2. Bonn train motion, simulated detections ----

void runBonnTrain(IdentityRun& run, IdentityFigures& out) {
  const std::string train = run.options.data + "/bonn-posetrack/annotations/train";
  if (!fs::exists(train)) return;
  run.log("Bonn train motion with simulated detections");
  MarkdownTable table({{"stride", true},
                       {"similarity"},
                       {"MOTA", true},
                       {"joint id switches", true},
                       {"IDF1", true},
                       {"person id switches", true}});
  for (int stride : {1, 3}) {
    const auto sims = simulateFolder(train, stride, Noise{}, run.options.variant.seed + stride);
    for (const std::string name : {"oks", "iou", "pckh", "tff-oracle"}) {
      const SimRunResult r = trackSimulated(sims, name, run.defaults);
      json t = totalJson(r.eval);
      t["person_id_switches"] = r.id_switches;
      out.train.push_back({{"stride", stride}, {"similarity", name}, {"total", t}});
      table.row({std::to_string(stride), name, fixed(r.eval.total.mota, 1),
                 std::to_string(r.joint_id_switches), fixed(r.eval.total.idf1, 1),
                 std::to_string(r.id_switches)});
    }
  }
  out.train_md = table.str();
}

// ---- 3. vtest.avi ----

void runVtest(IdentityRun& run, IdentityFigures& out) {
  const IdentityOptions& o = run.options;
  if (!fs::exists(o.vtest)) return;
  cv::VideoCapture video(o.vtest);
  const int total = static_cast<int>(video.get(cv::CAP_PROP_FRAME_COUNT));
  const int n = o.vtest_frames > 0 ? std::min(o.vtest_frames, total) : total;
  const double video_fps = video.get(cv::CAP_PROP_FPS) > 0 ? video.get(cv::CAP_PROP_FPS) : 10;
  run.log("vtest.avi: " + std::to_string(n) + " frames");
  CachedFrame current;
  const auto runs = run.trackers->run(
      n,
      [&](int) -> const CachedFrame& {
        cv::Mat frame;
        if (!video.read(frame)) throw Error(o.vtest + ": cannot read a frame");
        current = estimateFrame(*run.model, frame);
        return current;
      },
      [&](int k) { return k / video_fps; },
      [&](int k) {
        if ((k + 1) % 100 == 0) run.log("  vtest: frame " + std::to_string(k + 1));
      });
  MarkdownTable table({{"similarity"},
                       {"ids, frames 1-300", true},
                       {"confirmed", true},
                       {"ids per person", true},
                       {"ids per visit", true},
                       {"ids, all " + std::to_string(n) + " frames", true},
                       {"confirmed", true},
                       {"ids per person", true},
                       {"ids per visit", true}});
  for (const TrackRun& tracks : runs) {
    std::set<std::int64_t> a300, c300, a, c;
    for (size_t f = 0; f < tracks.frames.size(); ++f)
      for (const TrackedPose& p : tracks.frames[f]) {
        a.insert(p.track_id);
        if (!p.tentative) c.insert(p.track_id);
        if (f < 300) {
          a300.insert(p.track_id);
          if (!p.tentative) c300.insert(p.track_id);
        }
      }
    auto per = [](size_t ids, int people) {
      return people > 0 ? static_cast<double>(ids) / people : std::nan("");
    };
    out.vtest[tracks.similarity] = {{"ids_300", a300.size()},
                                    {"confirmed_300", c300.size()},
                                    {"ids_all", a.size()},
                                    {"confirmed_all", c.size()},
                                    {"frames", n},
                                    {"tracker_seconds", tracks.seconds}};
    table.row({tracks.similarity, std::to_string(a300.size()), std::to_string(c300.size()),
               fixed(per(a300.size(), kVtestPeopleFirst300), 2),
               fixed(per(a300.size(), kVtestVisitsFirst300), 2), std::to_string(a.size()),
               std::to_string(c.size()), fixed(per(a.size(), kVtestPeopleAll), 2),
               fixed(per(a.size(), kVtestVisitsAll), 2)});
  }
  out.vtest_md = table.str();
  for (const TrackRun& tracks : runs)
    if (!o.vtest_sheet.empty() && tracks.similarity == o.sheet_similarity) {
      writeVisitSheet(o.vtest, tracks.frames, video_fps, o.vtest_sheet);
      run.log("wrote " + o.vtest_sheet);
      out.vtest_md += "\n" + tracks.similarity +
                      "'s tracks, a crop per id and visit (a visit ends where the id is not seen "
                      "for a second; a row is one id, numbered from 1 in the order first shown): "
                      "a row holding two people is an id that passed from one to the other, a "
                      "person in two rows got a second id.\n\n![vtest.avi, " +
                      tracks.similarity + ": a crop per id and visit](" +
                      fs::path(o.vtest_sheet).filename().string() + ")\n";
    }
  out.vtest["people_by_eye_300"] = kVtestPeopleFirst300;
  out.vtest["visits_by_eye_300"] = kVtestVisitsFirst300;
  out.vtest["people_by_eye_all"] = kVtestPeopleAll;
  out.vtest["visits_by_eye_all"] = kVtestVisitsAll;
}

// ---- 5. Association time ----

void runTiming(IdentityRun& run, IdentityFigures& out) {
  const std::vector<std::string>& similarities = run.options.similarities;
  std::ostringstream md;
  run.log("association timing");
  for (int people : {20, 30}) {
    const AssociationTiming t = timeTffPotentials(people, run.defaults.line_samples);
    out.timing["tff_potentials_" + std::to_string(people) + "x" + std::to_string(people)] = {
        {"potentials_ms", t.potentials_ms},
        {"with_greedy_ms", t.with_greedy_ms},
        {"wall_ms", t.wall_ms},
        {"best_ms", t.best_ms}};
    md << "- TFF potentials of " << people << " tracks x " << people
       << " poses + greedy matching: " << fixed(t.with_greedy_ms, 3) << " ms (potentials alone "
       << fixed(t.potentials_ms, 3) << " ms)\n";
  }
  // Real frames for the camera motion and "flow": corners, texture and motion as in use (one
  // frame over and over would let Lucas-Kanade stop at its first step).
  std::vector<cv::Mat> greys;
  cv::VideoCapture video(run.options.vtest);
  for (cv::Mat frame; greys.size() < 10 && video.read(frame);) {
    cv::Mat grey;
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
    cv::resize(grey, grey, {960, 540});
    greys.push_back(grey);
  }
  if (greys.empty()) {  // no vtest.avi: noise, which tracks at least
    greys.emplace_back(540, 960, CV_8U);
    cv::randu(greys[0], 0, 255);
  }
  for (const bool camera : {true, false}) {
    TrackerSettings s = run.defaults;
    s.camera_compensation = camera;
    const std::string key = camera ? "update_20_ms" : "update_20_ms_no_camera_motion";
    md << "- one whole `PoseAssociator::update` per frame, 20 people (each missed in one frame in "
          "ten: lost tracks, re-identification), "
       << (camera ? "the defaults (camera motion estimated on 10 vtest.avi frames played forward "
                    "and back)"
                  : "camera_compensation off")
       << ", median CPU ms: ";
    for (size_t i = 0; i < similarities.size(); ++i) {
      const double ms = timeAssociatorUpdate(similarities[i], 20, s, greys);
      out.timing[key][similarities[i]] = ms;
      md << (i ? ", " : "") << similarities[i] << " " << fixed(ms, 3);
    }
    md << "\n";
  }
  out.timing_md = md.str();
}

}  // namespace

std::optional<BonnSequence> readBonnSequence(const std::string& bonn_gt,
                                             const std::string& bonn_root,
                                             const VariantOptions& options) {
  if (!fs::exists(bonn_gt)) return std::nullopt;
  BonnSequence bonn;
  bonn.source = pt::readSequence(bonn_gt);
  for (const pt::Frame& f : bonn.source.frames) {
    bonn.images.push_back(cv::imread(bonn_root + "/" + f.file_name, cv::IMREAD_COLOR));
    if (bonn.images.back().empty()) throw Error(bonn_root + "/" + f.file_name + ": cannot read");
  }
  bonn.size = bonn.images.front().size();
  bonn.variants = bonnVariants(static_cast<int>(bonn.images.size()), bonn.size, options);
  return bonn;
}

std::vector<IdentityCase> identityCases(const IdentityRun& run) {
  std::vector<IdentityCase> cases;
  // First, before any OpenVINO pipeline has run in this process. After one (the live-bonn
  // case), this cv::dnn live pipeline took 56-69 s for its 30 s of video instead of 31 s: the
  // first 100 frames ran at the normal pace (11 s), then cv::dnn's threads used about one core
  // of the two. The offline run was not slowed. Not explained yet (both engines share Debian's
  // TBB runtime).
  cases.push_back(
      {"live", "", "vtest.avi through a live leaky-queue pipeline against offline", runLiveVtest});
  if (run.bonn) {
    // By index: the case runs against the IdentityRun it is handed, not this one.
    for (size_t i = 0; i < run.bonn->variants.size(); ++i)
      cases.push_back(
          {run.bonn->variants[i].name, "bonn",
           "the Bonn test sequence, " + run.bonn->variants[i].description,
           [i](IdentityRun& r, IdentityFigures& out) { runVariant(r, out, r.bonn->variants[i]); }});
    cases.push_back(
        {"live-bonn", "", "the Bonn sequence as a live camera, offline against live", runLiveBonn});
    cases.push_back(
        {"camera", "", "the camera motion estimate against the variants' exact motion", runCamera});
  }
  cases.push_back(
      {"bonn-train", "", "the Bonn train motion with simulated detections", runBonnTrain});
  cases.push_back(
      {"vtest", "", "distinct ids on vtest.avi against the people counted by eye", runVtest});
  cases.push_back({"timing", "", "the association time per frame for 20 people", runTiming});
  return cases;
}

}  // namespace jointflow::bench
