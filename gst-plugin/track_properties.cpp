// The rows of jointflowtrack's properties (track_properties.hpp).
#include "track_properties.hpp"

namespace jointflow::gst {
namespace {

using E = TrackElementSettings;

std::vector<SettingSpec<E>> makeRows() {
  std::vector<SettingSpec<E>> rows = nestSettings(trackerSettingsSchema(), &E::tracker);
  // The element's own rows apply while frames flow (live = true).
  rows.push_back(memberSetting<E>(
      {"inference-interval", "Inference interval",
       "Run the networks on every Nth frame; the poses of the frames in between are moved on "
       "with each track's velocity",
       SettingKind::kUInt, 1, 1000, nullptr, true},
      &E::inference_interval));
  rows.push_back(memberSetting<E>(
      {"skip-late-frames", "Skip late frames",
       "When downstream reports lateness (QoS), predict the poses of frames that are already "
       "late instead of running the networks",
       SettingKind::kBool, 0, 0, nullptr, true},
      &E::skip_late_frames));
  rows.push_back(memberSetting<E>(
      {"async-inference", "Asynchronous inference",
       "With an asynchronous engine (backend=openvino), hold one frame so that the network of "
       "each frame runs while the frame before is associated and pushed and upstream brings the "
       "next (one frame of latency, reported); false: each frame leaves with its own poses "
       "before the next is taken (docs/benchmarks.md measures both)",
       SettingKind::kBool, 0, 0, nullptr, false},
      &E::async_inference));
  // Stream time, as every time-based setting: a file is reported per seconds of video however
  // fast it runs, and an outage (no frames) posts nothing, as nothing of the element changes.
  rows.push_back(memberSetting<E>(
      {"stats-interval", "Statistics interval",
       "Seconds of stream time between two \"jointflowtrack-stats\" element messages (frames "
       "in, inferred, predicted; tracks; inference, element and live lag histograms; models; "
       "docs/gstreamer.md), and one at the end of the stream; 0 = none",
       SettingKind::kFloat, 0, 86400, nullptr, true},
      &E::stats_interval));
  return rows;
}

}  // namespace

const std::vector<SettingSpec<TrackElementSettings>>& trackProperties() {
  static const std::vector<SettingSpec<E>> rows = makeRows();
  return rows;
}

}  // namespace jointflow::gst
