// Validation of the tracker settings: each setting's range is its row's (settings_schema.cpp),
// and only the checks across settings are written here.
#include <sstream>
#include <string>

#include "jointflow/error.hpp"
#include "jointflow/pose_associator.hpp"
#include "jointflow/settings_schema.hpp"

namespace jointflow {
namespace {

std::string text(float v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

void validateTrackerSettings(const TrackerSettings& s) {
  checkSettings(trackerSettingsSchema(), s);
  // The TFF keeps 1 - both weights; a float's rounding (0.3 + 0.7) is not the user's fault.
  if (!(s.tff_flow_weight <= 1.f - s.tff_oks_weight + 1e-6f))
    throw Error("tff-flow-weight: " + text(s.tff_flow_weight) +
                " is out of range, expected [0, 1 - tff-oks-weight] = [0, " +
                text(1.f - s.tff_oks_weight) +
                "] (the TFF's weight is 1 - both; lower one of them)");
}

// The schema's rows are TrackerSettings' (one list, in the order front ends show them): the
// association's part is checked inside default settings, whose other rows are valid.
void validateAssociationSettings(const AssociationSettings& s) {
  TrackerSettings whole;
  static_cast<AssociationSettings&>(whole) = s;
  validateTrackerSettings(whole);
}

}  // namespace jointflow
