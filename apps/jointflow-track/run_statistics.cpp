// Counting a jointflow-track run (run_statistics.hpp).
#include "run_statistics.hpp"

namespace jointflow::cli {

void RunStatistics::record(const GstJointFlowMeta* meta) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++frames_;
  const guint n = meta ? gst_jointflow_meta_get_n_persons(meta) : 0;
  detections_ += n;
  for (guint i = 0; i < n; ++i) {
    const JointFlowPerson* p = gst_jointflow_meta_get_person(meta, i);
    tracks_.insert(p->track_id);
    if (!p->tentative) confirmed_.insert(p->track_id);
  }
}

RunCounts RunStatistics::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {frames_, detections_, tracks_.size(), confirmed_.size()};
}

}  // namespace jointflow::cli
