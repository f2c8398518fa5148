// assoc-bench: association only, on real human motion with identities (the Bonn PoseTrack train
// ground truth, no images). The ground-truth poses get simulated detector noise (joint jitter,
// missed joints, missed and false people), every similarity gets the same detections at frame
// strides 1-4, and the tracks are scored with the poseval-equivalent evaluation
// (jointflow/evaluation.hpp). "tff-oracle" is the TFF rendered from the ground truth (paper
// Eq. 2-4), i.e. what a perfect TFF network would give. Also times the association of 30 by 30
// people with the TFF integral on one core.
//
//   assoc-bench --data DIR [--stride N] [--json] [--seed S]
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "jointflow/error.hpp"
#include "jointflow/evaluation.hpp"
#include "jointflow/matching.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/similarity.hpp"
#include "jointflow/temporal_flow.hpp"

using namespace jointflow;
namespace pt = jointflow::posetrack;

namespace {

// What the simulated detector gets wrong.
struct Noise {
  double jitter = 0.1;        ///< joint jitter, standard deviation in head sizes
  double miss_joint = 0.1;    ///< probability that a joint is not detected
  double miss_person = 0.05;  ///< probability that a person is not detected in a frame
  double false_person = 0.1;  ///< expected false people per frame
};

// One detection: the PoseTrack joints written to the predictions, the COCO pose the tracker sees,
// and the ground-truth identity (-1 for a false person).
struct Detection {
  pt::PoseTrackJoints joints;
  Pose pose;
  std::int64_t identity = -1;
};

struct SimFrame {
  std::vector<Detection> detections;
  std::map<std::int64_t, Pose> truth;  ///< clean ground truth by identity, for the oracle TFF
};

struct SimSequence {
  pt::Sequence ground_truth;  ///< the frames kept at this stride
  std::vector<SimFrame> frames;
  cv::Size frame_size;
  double frame_seconds = 0.04;  ///< stream time between kept frames (stride / 25 frames/s)
};

double headSize(const pt::HeadBox& b) {
  return 0.6 * std::hypot(b.x2 - b.x1, b.y2 - b.y1);
}

Pose cocoPose(const pt::PoseTrackJoints& joints, float score) {
  Pose p;
  for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
    const int coco = pt::kCocoOfPoseTrackJoint[j];
    if (coco < 0 || !joints[j]) continue;  // neck and head top have no COCO joint
    p.keypoints[coco] = {static_cast<float>(joints[j]->x), static_cast<float>(joints[j]->y), 1.f};
  }
  p.score = score;
  p.box = p.keypointBox(0.f);
  return p;
}

SimSequence simulate(const pt::Sequence& gt, int stride, const Noise& noise, std::mt19937& rng) {
  SimSequence sim;
  sim.ground_truth = gt;
  sim.ground_truth.frames.clear();
  sim.frame_seconds = stride / 25.0;  // PoseTrack's videos run at about 25 frames/s
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::poisson_distribution<int> false_count(noise.false_person);
  double max_x = 64, max_y = 64;
  for (const pt::Frame& f : gt.frames)
    for (const pt::Person& p : f.people)
      for (const auto& j : p.joints)
        if (j) max_x = std::max(max_x, j->x), max_y = std::max(max_y, j->y);
  sim.frame_size = {static_cast<int>(std::ceil((max_x + 32) / 4)) * 4,
                    static_cast<int>(std::ceil((max_y + 32) / 4)) * 4};

  for (size_t i = 0; i < gt.frames.size(); i += stride) {
    const pt::Frame& f = gt.frames[i];
    sim.ground_truth.frames.push_back(f);
    SimFrame frame;
    for (const pt::Person& person : f.people) {
      const std::int64_t id = person.track_id.value_or(-1);
      frame.truth[id] = cocoPose(person.joints, 1.f);
      if (uniform(rng) < noise.miss_person) continue;
      const double head = person.head_box ? headSize(*person.head_box) : 20.0;
      Detection d;
      d.identity = id;
      for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
        if (!person.joints[j] || uniform(rng) < noise.miss_joint) continue;
        pt::PoseTrackPoint q = *person.joints[j];
        q.x += noise.jitter * head * gauss(rng);
        q.y += noise.jitter * head * gauss(rng);
        q.score = 1.0;
        d.joints[j] = q;
      }
      d.pose = cocoPose(d.joints, static_cast<float>(0.5 + 0.5 * uniform(rng)));
      frame.detections.push_back(d);
    }
    // False people: a person of another frame of the sequence at a random place.
    for (int k = false_count(rng); k > 0; --k) {
      const pt::Frame& other =
          gt.frames[std::uniform_int_distribution<size_t>(0, gt.frames.size() - 1)(rng)];
      if (other.people.empty()) continue;
      const pt::Person& src =
          other.people[std::uniform_int_distribution<size_t>(0, other.people.size() - 1)(rng)];
      const double dx = (uniform(rng) - 0.5) * sim.frame_size.width;
      const double dy = (uniform(rng) - 0.5) * sim.frame_size.height * 0.5;
      Detection d;
      for (int j = 0; j < pt::kNumPoseTrackJoints; ++j) {
        if (!src.joints[j]) continue;
        pt::PoseTrackPoint q = *src.joints[j];
        q.x += dx;
        q.y += dy;
        q.score = 1.0;
        d.joints[j] = q;
      }
      d.pose = cocoPose(d.joints, static_cast<float>(0.2 + 0.4 * uniform(rng)));
      frame.detections.push_back(d);
    }
    std::shuffle(frame.detections.begin(), frame.detections.end(), rng);
    sim.frames.push_back(std::move(frame));
  }
  return sim;
}

// The oracle TFF between two simulated frames: every ground-truth person in both, clean.
cv::Mat oracleTff(const SimFrame& previous, const SimFrame& current, cv::Size frame,
                  const GridTransform& grid) {
  std::vector<JointMotion> motions;
  for (const auto& [id, pose] : current.truth) {
    auto it = previous.truth.find(id);
    if (it == previous.truth.end()) continue;
    const auto m = jointMotions(it->second, pose, grid, 0.f);
    motions.insert(motions.end(), m.begin(), m.end());
  }
  return renderTemporalFlowField(motions, kNumJoints, {frame.width / 4, frame.height / 4}, 1.f);
}

struct RunResult {
  double mota = 0.0;
  std::int64_t id_switches = 0;        ///< person level: an identity reported under a new id
  std::int64_t joint_id_switches = 0;  ///< poseval's, summed over the joint classes
};

// Tracks every sequence with one similarity and scores the result. The MOTA comes from the
// evaluation library (one call), in percent as poseval reports it.
RunResult track(const std::vector<SimSequence>& sims, const std::string& similarity,
                TrackerSettings settings) {
  const bool oracle = similarity == "tff-oracle";
  settings.similarity = oracle ? SimilarityType::kTff : parseEnum<SimilarityType>(similarity);
  const GridTransform grid{4.f, 4.f, 0.f, 0.f};
  RunResult result;
  std::vector<pt::Sequence> truth, predictions;
  for (const SimSequence& sim : sims) {
    PoseAssociator associator(settings);
    pt::TrackIdMap ids;
    pt::Sequence pred = sim.ground_truth;
    std::map<std::int64_t, std::int64_t> last_id;
    for (size_t t = 0; t < sim.frames.size(); ++t) {
      const SimFrame& frame = sim.frames[t];
      AssociationFrame in;
      for (const Detection& d : frame.detections) in.poses.push_back(d.pose);
      in.grid_to_frame = grid;
      in.time = t * sim.frame_seconds;
      if (oracle && t > 0) in.tff = oracleTff(sim.frames[t - 1], frame, sim.frame_size, grid);
      const std::vector<TrackedPose> tracked = associator.update(in);
      std::vector<std::int64_t> tracker_ids;
      for (const TrackedPose& tp : tracked) tracker_ids.push_back(tp.track_id);
      const std::vector<int> numbers = ids.assign(tracker_ids);
      pt::Frame& out = pred.frames[t];
      out.people.clear();
      out.ignore_regions.clear();
      for (size_t k = 0; k < tracked.size(); ++k) {
        const Detection& d = frame.detections[tracked[k].detection];
        pt::Person p;
        p.track_id = numbers[k];
        p.joints = d.joints;
        p.score = d.pose.score;
        p.head_box.reset();
        out.people.push_back(p);
        if (d.identity < 0) continue;
        auto [it, inserted] = last_id.emplace(d.identity, tracked[k].track_id);
        if (!inserted && it->second != tracked[k].track_id) {
          ++result.id_switches;
          it->second = tracked[k].track_id;
        }
      }
    }
    truth.push_back(sim.ground_truth);
    predictions.push_back(std::move(pred));
  }
  const PoseTrackEvalResult eval = evaluatePoseTrack(truth, predictions);
  result.mota = eval.total.mota;
  result.joint_id_switches = eval.total.counts.switches;
  return result;
}

// CPU time of the calling thread in ms: the time on one core, whatever else the machine runs.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Timing {
  double potentials_ms = 0.0;   ///< Psi of 30 x 30 people by the TFF integral
  double with_greedy_ms = 0.0;  ///< the same plus greedy matching
  double wall_ms = 0.0;         ///< wall-clock time of the latter
  double best_ms = 0.0;         ///< the fastest run with greedy matching (least disturbed)
};

// Association of 30 tracks with 30 new poses: Psi by the TFF integral + greedy matching, median
// of 200 runs, on one core (the association is single-threaded).
Timing timeTff30x30(int line_samples) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> x(0.f, 960.f), y(0.f, 540.f);
  Poses previous(30), current(30);
  for (Poses* poses : {&previous, &current})
    for (Pose& p : *poses) {
      for (Keypoint& k : p.keypoints) k = {x(rng), y(rng), 1.f};
      p.score = 1.f;
    }
  const int sizes[] = {1, 34, 135, 240};  // a 960 x 540 frame on a stride-4 grid
  SimilarityInput in;
  in.tff = cv::Mat(4, sizes, CV_32F);
  cv::randu(in.tff, -1.f, 1.f);
  in.grid_to_frame = {4.f, 4.f, 0.f, 0.f};
  SimilarityOptions options;
  options.line_samples = line_samples;
  const auto similarity = createSimilarity(SimilarityType::kTff, options);
  std::vector<double> psi_ms, total_ms, wall_ms;
  for (int rep = 0; rep < 200; ++rep) {
    const auto w0 = std::chrono::steady_clock::now();
    const double t0 = threadCpuMs();
    const Potentials p = similarity->compute(previous, current, in);
    const double t1 = threadCpuMs();
    const auto matches = matchGreedy(p.psi, p.per_joint, 0.f);
    const double t2 = threadCpuMs();
    const auto w1 = std::chrono::steady_clock::now();
    if (matches.size() > 30) std::abort();  // keeps the work observable
    psi_ms.push_back(t1 - t0);
    total_ms.push_back(t2 - t0);
    wall_ms.push_back(std::chrono::duration<double, std::milli>(w1 - w0).count());
  }
  auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double best = *std::min_element(total_ms.begin(), total_ms.end());
  return {median(psi_ms), median(total_ms), median(wall_ms), best};
}

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
    std::vector<pt::Sequence> sequences;
    for (const std::string& file : pt::listSequenceFiles(data))
      sequences.push_back(pt::readSequence(file));
    const std::vector<std::string> similarities = {"oks", "iou", "pckh", "tff-oracle"};
    std::vector<int> strides = {1, 2, 3, 4};
    if (stride) strides = {stride};

    nlohmann::json results = nlohmann::json::array();
    std::ostringstream table;
    table << std::fixed << std::setprecision(1);
    table << "| similarity | stride | MOTA % | id switches (persons) | id switches (joints, "
             "poseval) |\n"
          << "|---|---|---|---|---|\n";
    for (int s : strides) {
      std::mt19937 rng(seed + s);
      std::vector<SimSequence> sims;
      for (const pt::Sequence& seq : sequences) {
        // poseval's tracking needs at least two frames (it drops the last one).
        if ((seq.frames.size() + s - 1) / s < 3) continue;
        sims.push_back(simulate(seq, s, noise, rng));
      }
      for (const std::string& name : similarities) {
        const RunResult r = track(sims, name, settings);
        results.push_back({{"similarity", name},
                           {"stride", s},
                           {"mota", r.mota},
                           {"id_switches", r.id_switches},
                           {"joint_id_switches", r.joint_id_switches}});
        table << "| " << name << " | " << s << " | " << r.mota << " | " << r.id_switches << " | "
              << r.joint_id_switches << " |\n";
      }
    }
    const Timing timing = timeTff30x30(settings.line_samples);
    if (json) {
      std::cout << nlohmann::json{{"results", results},
                                  {"tff_30x30_ms",
                                   {{"potentials", timing.potentials_ms},
                                    {"with_greedy", timing.with_greedy_ms},
                                    {"wall", timing.wall_ms},
                                    {"best_with_greedy", timing.best_ms}}}}
                       .dump(1)
                << "\n";
    } else {
      std::cout << "Association on " << sequences.size() << " sequences of " << data
                << "\nnoise: jitter " << noise.jitter << " head sizes, missed joints "
                << noise.miss_joint << ", missed people " << noise.miss_person
                << ", false people/frame " << noise.false_person << ", seed " << seed << "\n\n"
                << table.str() << "\n"
                << std::setprecision(3) << "TFF association of 30 x 30 people (17 joints x "
                << settings.line_samples
                << " samples), median of 200 runs, CPU time of one core: " << timing.potentials_ms
                << " ms potentials, " << timing.with_greedy_ms << " ms with greedy matching ("
                << timing.wall_ms << " ms wall clock); fastest run " << timing.best_ms << " ms\n";
    }
  } catch (const Error& e) {
    std::cerr << "assoc-bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
