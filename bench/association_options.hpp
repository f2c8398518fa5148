// The association settings the tracking benchmarks (identity-bench, track-quality) let a run
// change from main's defaults, declared once so both take them in the same form and write them
// into the command that regenerates their document.
#pragma once

#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "jointflow/tracker.hpp"

namespace jointflow::bench {

struct AssociationOptions {
  float tau_delta = TrackerSettings{}.tau_delta;
  float tff_oks_weight = TrackerSettings{}.tff_oks_weight;
  float tff_flow_weight = TrackerSettings{}.tff_flow_weight;
  float auto_tff_gap = TrackerSettings{}.auto_tff_gap;
  std::string tff_model;  ///< empty: TrackerSettings' default (models/tff_<spatial model>.onnx)
  bool camera_compensation = TrackerSettings{}.camera_compensation;

  void addTo(CLI::App& app) {
    app.add_option("--tau-delta", tau_delta, "TrackerSettings::tau_delta, frame px")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--tff-oks-weight", tff_oks_weight, "TrackerSettings::tff_oks_weight")
        ->check(CLI::Range(0.f, 1.f))
        ->capture_default_str();
    app.add_option("--tff-flow-weight", tff_flow_weight, "TrackerSettings::tff_flow_weight")
        ->check(CLI::Range(0.f, 1.f))
        ->capture_default_str();
    app.add_option("--auto-tff-gap", auto_tff_gap, "TrackerSettings::auto_tff_gap, seconds")
        ->check(CLI::Range(0.f, 3600.f))
        ->capture_default_str();
    app.add_option("--tff-model", tff_model,
                   "TFF ONNX file (default: models/tff_<spatial model>.onnx), e.g. a network "
                   "training/retrain.sh made, before it is shipped");
    app.add_flag("--camera-compensation,!--no-camera-compensation", camera_compensation,
                 "TrackerSettings::camera_compensation (default on); off: what each similarity "
                 "does where the camera's motion is not estimated");
  }

  /// `settings` with these options (its tff_model only where one was given).
  void applyTo(TrackerSettings& settings) const {
    settings.tau_delta = tau_delta;
    settings.tff_oks_weight = tff_oks_weight;
    settings.tff_flow_weight = tff_flow_weight;
    settings.auto_tff_gap = auto_tff_gap;
    settings.camera_compensation = camera_compensation;
    if (!tff_model.empty()) settings.tff_model = tff_model;
  }

  /// The options as jointflowtrack properties ("name=value ..."), those that differ from the
  /// defaults only: the live cases run the element, not a Tracker.
  std::string elementProperties() const {
    const TrackerSettings defaults;
    std::ostringstream s;
    if (tau_delta != defaults.tau_delta) s << " tau-delta=" << tau_delta;
    if (tff_oks_weight != defaults.tff_oks_weight) s << " tff-oks-weight=" << tff_oks_weight;
    if (tff_flow_weight != defaults.tff_flow_weight) s << " tff-flow-weight=" << tff_flow_weight;
    if (auto_tff_gap != defaults.auto_tff_gap) s << " auto-tff-gap=" << auto_tff_gap;
    if (!tff_model.empty()) s << " tff-model=\"" << tff_model << "\"";
    if (camera_compensation != defaults.camera_compensation) s << " camera-compensation=false";
    const std::string text = s.str();
    return text.empty() ? text : text.substr(1);
  }

  /// The options as typed on a command line.
  std::string commandLine() const {
    std::ostringstream s;
    s << "--tau-delta " << tau_delta << " --tff-oks-weight " << tff_oks_weight
      << " --tff-flow-weight " << tff_flow_weight << " --auto-tff-gap " << auto_tff_gap;
    if (!tff_model.empty()) s << " --tff-model " << tff_model;
    if (!camera_compensation) s << " --no-camera-compensation";
    return s.str();
  }
};

}  // namespace jointflow::bench
