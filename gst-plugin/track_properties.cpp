// The rows of jointflowtrack's properties (track_properties.hpp).
#include "track_properties.hpp"

namespace jointflow::gst {
namespace {

using E = TrackElementSettings;

SettingSpec<E> elementRow(SettingInfo info, std::function<SettingValue(const E&)> get,
                          std::function<void(E&, const SettingValue&)> set) {
  SettingSpec<E> r;
  static_cast<SettingInfo&>(r) = info;
  r.get = std::move(get);
  r.set = std::move(set);
  return r;
}

std::vector<SettingSpec<E>> makeRows() {
  std::vector<SettingSpec<E>> rows = nestSettings(trackerSettingsSchema(), &E::tracker);
  rows.push_back(elementRow(
      {"inference-interval", "Inference interval",
       "Run the networks on every Nth frame; the poses of the frames in between are moved on "
       "with each track's velocity",
       SettingKind::kUInt, 1, 1000, nullptr, true},
      [](const E& s) { return SettingValue{s.inference_interval}; },
      [](E& s, const SettingValue& v) { s.inference_interval = std::get<unsigned>(v); }));
  rows.push_back(elementRow(
      {"skip-late-frames", "Skip late frames",
       "When downstream reports lateness (QoS), predict the poses of frames that are already "
       "late instead of running the networks",
       SettingKind::kBool, 0, 0, nullptr, true},
      [](const E& s) { return SettingValue{s.skip_late_frames}; },
      [](E& s, const SettingValue& v) { s.skip_late_frames = std::get<bool>(v); }));
  return rows;
}

}  // namespace

const std::vector<SettingSpec<TrackElementSettings>>& trackProperties() {
  static const std::vector<SettingSpec<E>> rows = makeRows();
  return rows;
}

}  // namespace jointflow::gst
