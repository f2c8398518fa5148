// identity-bench's cases (bench/identity.cpp has what each measures and why): each a name that
// --cases selects, a line saying what it measures, and a function that runs it and adds its
// figures to IdentityFigures; identity_document.hpp writes those as docs/identity.md and .json.
// Split from the program's main so that the benchmark reads like the tests: a list of named
// cases, an option parser that picks some, a writer.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "cached_tracking.hpp"
#include "jointflow/posetrack.hpp"
#include "jointflow/spatial_model.hpp"
#include "jointflow/tracker.hpp"
#include "live_cases.hpp"
#include "variants.hpp"

namespace jointflow::bench {

// People in vtest.avi, counted by eye once for this benchmark: how they were counted, and who
// they are, is in bench/identity.cpp (docs/identity.md and the tests point there).
constexpr int kVtestPeopleFirst300 = 9;
constexpr int kVtestVisitsFirst300 = 11;
constexpr int kVtestPeopleAll = 11;
constexpr int kVtestVisitsAll = 20;

/// identity-bench's command line, as bench/identity.cpp parses it.
struct IdentityOptions {
  std::string data;   ///< the data folder (bonn-posetrack/ inside)
  std::string vtest;  ///< vtest.avi
  std::vector<std::string> similarities;
  int vtest_frames = 0;  ///< 0: all
  int live_frames = 300;
  float joint_threshold = 0.3f;
  VariantOptions variant;
  LiveBonnOptions live_bonn;    ///< its similarities, properties and threshold as the others'
  std::string predictions_dir;  ///< empty: the Bonn cases' tracks are not written
  std::string vtest_sheet;      ///< empty: no contact sheet of vtest.avi's tracks
  std::string sheet_similarity;
};

/// The Bonn test sequence, read once: the variant, live-bonn and camera cases all start from it.
struct BonnSequence {
  posetrack::Sequence source;
  std::vector<cv::Mat> images;
  cv::Size size;
  std::vector<Variant> variants;
  std::vector<CachedFrame> still;  ///< the source frames as they are, once a case needs them
};

/// What every case reads: the options, main's default TrackerSettings (only the similarity
/// changes), one tracker per similarity and one spatial model shared by the cases, so that each
/// similarity gets the same detections.
struct IdentityRun {
  IdentityOptions options;
  TrackerSettings defaults;
  std::unique_ptr<SimilarityTrackers> trackers;
  std::unique_ptr<SpatialModel> model;
  Log log;
  std::filesystem::path scratch;     ///< the live cases' clips and JSON files (they remove them)
  std::optional<BonnSequence> bonn;  ///< absent without the data
};

/// The Bonn test sequence (`bonn_gt`, its images under `bonn_root`) and its variants, or nothing
/// where the ground truth is absent.
std::optional<BonnSequence> readBonnSequence(const std::string& bonn_gt,
                                             const std::string& bonn_root,
                                             const VariantOptions& options);

/// One Bonn variant's scores with one similarity.
struct CaseRow {
  std::string name, similarity;
  nlohmann::json total;
  int frames = 0;
  int ids = 0;
};

/// Every figure of a run; a case fills its part, the rest stays empty (and out of the document).
struct IdentityFigures {
  std::string notes;          ///< what could not run and why, at the top of the document
  std::vector<CaseRow> rows;  ///< the Bonn variants, each similarity
  std::string variants_md;    ///< a line per variant run: what it is
  nlohmann::json occluder = nlohmann::json::object();
  std::string occluder_md;  ///< how long the bar hides people
  nlohmann::json camera = nlohmann::json::object();
  std::string camera_md;
  nlohmann::json train = nlohmann::json::array();
  std::string train_md;
  nlohmann::json vtest = nlohmann::json::object();
  std::string vtest_md;
  LiveCase live_vtest, live_bonn;
  nlohmann::json timing = nlohmann::json::object();
  std::string timing_md;
};

struct IdentityCase {
  std::string name;      ///< what --cases selects it by
  std::string group;     ///< also selects it ("bonn": every variant); may be empty
  std::string measures;  ///< one line, for a reader of the list
  std::function<void(IdentityRun&, IdentityFigures&)> run;
};

/// The cases in the order they run: the vtest.avi live case first (see identity_cases.cpp), then
/// the Bonn variants (only where the sequence was read), live-bonn, camera, bonn-train, vtest,
/// timing.
std::vector<IdentityCase> identityCases(const IdentityRun& run);

}  // namespace jointflow::bench
