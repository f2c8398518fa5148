#include "mot_output.hpp"

#include "jointflow/error.hpp"
#include "jointflow/mot_evaluation.hpp"

namespace jointflow::cli {

MotOutput::MotOutput(const std::string& file) : out_(file), file_(file) {
  if (!out_) throw Error("cannot write the MOT file " + file);
}

void MotOutput::addFrame(std::int64_t index, const GstJointFlowMeta* meta) {
  for (guint i = 0; meta && i < gst_jointflow_meta_get_n_persons(meta); ++i) {
    const JointFlowPerson& p = *gst_jointflow_meta_get_person(meta, i);
    mot::Box box;
    box.id = p.track_id;
    box.x = p.x, box.y = p.y, box.w = p.width, box.h = p.height;
    box.confidence = p.score;
    out_ << mot::motLine(index + 1, box) << '\n';
  }
  out_.flush();
  if (!out_) throw Error("writing the MOT file " + file_ + " failed");
}

}  // namespace jointflow::cli
