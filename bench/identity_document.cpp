// identity-bench's writer (identity_document.hpp): the prose around each case's figures, the
// tables, the JSON. Sections without figures (their cases not selected or without data) are left
// out.
#include "identity_document.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <thread>

#include "markdown_table.hpp"
#include "text_format.hpp"

namespace jointflow::bench {
namespace {

using json = nlohmann::json;

/// The Bonn variants, a row per case, a column per similarity (in --similarities' order).
std::string casesTable(const std::vector<CaseRow>& rows,
                       const std::vector<std::string>& similarities) {
  std::vector<MarkdownTable::Column> columns = {{"case"}, {"frames", true}};
  for (const std::string& s : similarities) columns.push_back({s});
  MarkdownTable table(columns);
  std::vector<std::string> order;
  for (const CaseRow& r : rows)
    if (std::find(order.begin(), order.end(), r.name) == order.end()) order.push_back(r.name);
  auto num = [](const json& v, int d) {
    return v.is_null() ? std::string("n/a") : fixed(v.get<double>(), d);
  };
  for (const std::string& name : order) {
    std::vector<std::string> cells = {name};
    for (const CaseRow& r : rows) {
      if (r.name != name) continue;
      if (cells.size() == 1) cells.push_back(std::to_string(r.frames));
      cells.push_back(num(r.total["mota"], 1) + " / " + r.total["id_switches"].dump() + " [" +
                      r.total["id_switches_ground_truth_ids"].dump() + "] / " +
                      num(r.total["idf1"], 1) + " / " + r.total["person_id_switches"].dump() +
                      " [" + r.total["person_id_switches_ground_truth_ids"].dump() + "]");
    }
    table.row(cells);
  }
  return table.str();
}

std::string occluderTable(const json& occluder, const std::vector<std::string>& similarities) {
  MarkdownTable table({{"similarity"},
                       {"hidden episodes", true},
                       {"person matched before and after", true},
                       {"same id", true},
                       {"share", true},
                       {"episodes up to 2 s: same id", true}});
  for (const std::string& s : similarities) {
    if (!occluder.contains(s)) continue;
    const json& o = occluder[s];
    const int seen = o["seen_before_and_after"], same = o["same_id"];
    const int seen2 = o["seen_upto_2s"], same2 = o["same_id_upto_2s"];
    table.row({s, o["episodes"].dump(), std::to_string(seen), std::to_string(same),
               fixed(seen ? 100.0 * same / seen : std::nan(""), 0) + " %",
               std::to_string(same2) + " of " + std::to_string(seen2)});
  }
  return table.str();
}

}  // namespace

json identityJson(const IdentityFigures& f, const IdentityOptions& o, const IdentityRunInfo& info) {
  json doc = {{"command", info.command},
              {"settings",
               {{"model", info.model},
                {"input_size", info.input_size},
                {"joint_threshold", o.joint_threshold},
                {"fps", o.variant.fps}}}};
  json cases = json::array();
  for (const CaseRow& r : f.rows)
    cases.push_back(
        {{"case", r.name}, {"similarity", r.similarity}, {"frames", r.frames}, {"total", r.total}});
  doc["bonn_cases"] = cases;
  doc["occluder"] = f.occluder;
  doc["bonn_train"] = f.train;
  doc["vtest"] = f.vtest;
  doc["live"] = f.live_vtest.figures;
  doc["live_bonn"] = f.live_bonn.figures;
  doc["timing"] = f.timing;
  doc["camera_estimate"] = f.camera;
  doc["seconds"] = info.seconds;
  doc["load_average"] = {info.load_start, info.load_end};
  return doc;
}

std::string identityMarkdown(const IdentityFigures& f, const IdentityOptions& o,
                             const IdentityRunInfo& info) {
  std::ostringstream doc;
  doc << "# Identity benchmark\n\n"
      << "Written by `bench/identity.cpp` (`make bench-identity`, or `make bench`); the raw "
         "figures are in `"
      << info.json_name << "`. Default TrackerSettings, spatial model " << info.model
      << " at input size " << info.input_size << "; only the similarity changes. Took "
      << fixed(info.seconds / 60, 1) << " min on this machine ("
      << std::thread::hardware_concurrency() << " cores; 1-minute load average "
      << fixed(info.load_start, 1) << " at the start, " << fixed(info.load_end, 1)
      << " at the end).\n\n"
      << f.notes;
  if (!f.rows.empty()) {
    doc << "## Bonn test sequence and its variants\n\n"
        << "Each cell: MOTA / joint id switches [the same poses with the ground truth's ids] / "
           "IDF1 / person id switches [the same with the ground truth's ids] (the first three "
           "poseval-equivalent, jointflow-eval's "
           "defaults: MOTA a mean over joints, id switches summed over joints, IDF1 from the "
           "identity counts summed over joints; person id switches count a person shown under "
           "another id than the last time once, as CLEAR MOT counts boxes, so that one person "
           "under a new id for a frame, up to 30 joint id switches, reads as 2). MoveNet runs once "
           "per output frame and every "
           "similarity's Tracker gets the same SpatialResult. Joints scoring below "
        << o.joint_threshold
        << " are not written. In brackets: the id switches of the same poses with each "
           "pose given the id of the annotated person it holds the most joints of "
           "(bench/ground_truth_ids.hpp), what a tracker that always knew who is who would "
           "make with them. Those come from the poses (one holding or lying near joints of two "
           "people, two on one person), not from association; the rest from association.\n\n"
        << casesTable(f.rows, o.similarities)
        << "\nThe cases (frames made by the benchmark; the ground truth goes "
        << "through the same warp, joints out of the frame or under the bar are removed):\n\n"
        << f.variants_md << "\n";
  }
  if (!f.occluder.empty()) {
    doc << "### Occluder: back under the same id\n\n"
        << f.occluder_md << occluderTable(f.occluder, o.similarities)
        << "\nA person's id in a frame is the predicted id whose joints match at least half of "
           "its ground-truth joints within half a head size (best pairs first); before = the "
           "last such id before the person is fully hidden, after = the first one after.\n\n";
  }
  if (!f.camera.empty()) {
    doc << "### The camera motion estimate\n\n"
        << "CameraMotionTracker::update (core/tracking/camera_motion.hpp) on the grey frames "
           "of the cases, the ground-truth people of this and the previous frame left out, "
           "against the exact motion W_k W_k-1^-1 of the case's warps: per frame the mean "
           "distance between the estimated and the true position of a 5 x 5 grid of points "
           "spanning the frame. CPU ms on one thread (cv::setNumThreads(1)), rendering "
           "excluded.\n\n"
        << f.camera_md << "\n";
  }
  if (!f.train.empty()) {
    doc << "## Bonn train motion, simulated detections\n\n"
        << "The ground truth of the 30 Bonn train sequences (no images) with simulated "
           "detector noise (bench/assoc_sim.hpp: jitter 0.1 head sizes, 10 % joints and 5 % "
           "people missed, 0.1 false people per frame), through PoseAssociator. Without images "
           "there is no TFF network and no optical flow: tff-oracle is the TFF rendered from "
           "the ground truth (what a perfect network would give). Scored as poseval does but "
           "for its empty-frame rule: where a frame has no ground truth or no prediction, every "
           "person and joint counts (poseval counts one unpairable object and hypothesis per "
           "joint, so nose, which the train annotations never hold, scored -100 and pulled the "
           "mean over joints down by up to 12 points).\n\n"
        << f.train_md << "\n";
  }
  if (!f.vtest.empty()) {
    doc << "## vtest.avi\n\nNo ground truth: distinct ids against the people who appear, "
           "counted by eye once: "
        << kVtestPeopleFirst300 << " people in " << kVtestVisitsFirst300
        << " visits in frames 1-300, " << kVtestPeopleAll << " people in " << kVtestVisitsAll
        << " visits in the whole clip (a visit: from entering the view to leaving it; several "
           "people leave and come back). How they were counted, and who they are, is written "
           "in bench/identity.cpp. Confirmed: ids reported at least once as not tentative "
           "(min_track_length frames).\n\n"
        << f.vtest_md << "\n";
  }
  if (!f.live_bonn.markdown.empty()) {
    doc << "## The Bonn sequence as a live camera\n\n"
        << "The Bonn test sequence played forward and backward for " << o.live_bonn.frames
        << " frames into an MJPEG clip at " << fixed(o.live_bonn.fps, 0)
        << " frames/s, then through jointflowtrack as a user's gst-launch line runs it, with "
           "each similarity and each engine. Live: paced in real time by `identity "
           "sync=true`, a leaky queue of one buffer before the tracker (as the documented "
           "camera pipelines do), so the tracker gets the frames its engine keeps up with, at "
           "the gaps the queue leaves, with real timestamps and DISCONT flags. Offline: the "
           "same line without pacing and queue, every frame. Scored against the exact ground "
           "truth of the frames that reached the tracker; each cell as above: MOTA / joint id "
           "switches [the same poses with the ground truth's ids] / IDF1. Which frames reach "
           "the tracker live depends on the machine and its load, so the live figures move "
           "from run to run.\n\n"
        << f.live_bonn.markdown << "\n";
  }
  if (!f.live_vtest.markdown.empty()) {
    doc << "## Live pipeline against the offline run\n\nvtest.avi, the first " << o.live_frames
        << " frames, jointflowtrack's defaults (similarity "
        << toString(TrackerSettings{}.similarity)
        << "). Live: paced in real time by "
           "`identity sync=true`, a leaky queue of one buffer before the tracker (as the "
           "documented camera pipelines do). Offline: the same without pacing and queue.\n\n"
        << f.live_vtest.markdown << "\n";
  }
  if (!f.timing.empty()) {
    doc << "## Association time\n\nCPU time of the calling thread, median of 200 runs (frames); "
           "the whole update on one OpenCV thread (cv::setNumThreads(1)), since OpenCV's pool "
           "runs parts of Lucas-Kanade and of resizes on other threads, whose time the calling "
           "thread's does not count (with the pool the oks update measured 2.6 ms).\n\n"
        << f.timing_md << "\n";
  }
  return doc.str();
}

}  // namespace jointflow::bench
