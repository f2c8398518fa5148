// The properties of jointflowtrack: the tracker settings of the core's schema
// (trackerSettingsSchema) followed by the element's own (inference interval, late frames,
// asynchronous inference, statistics).
#pragma once

#include <gst/gst.h>

#include <vector>

#include "jointflow/settings_schema.hpp"
#include "jointflow/tracker.hpp"

namespace jointflow::gst {

/// Everything jointflowtrack's properties set. Defaults: TrackerSettings{} and the fields below.
struct TrackElementSettings {
  TrackerSettings tracker;
  /// Run the networks on every Nth frame and predict the poses in between.
  unsigned inference_interval = 1;
  /// Predict rather than infer the frames that downstream QoS reports late.
  bool skip_late_frames = true;
  /// With an asynchronous engine (OpenVINO): hold one frame so that its network runs while the
  /// frame before is associated and pushed and the next one comes in. Read at start.
  bool async_inference = true;
  /// Seconds of stream time between two statistics messages (track_stats.hpp); 0 = none.
  float stats_interval = 0.f;
};

/// The rows, in property-id order (id = index + 1).
const std::vector<SettingSpec<TrackElementSettings>>& trackProperties();

}  // namespace jointflow::gst
