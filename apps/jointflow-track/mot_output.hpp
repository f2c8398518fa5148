// jointflow-track's MOTChallenge output (--output-mot): one line per person and frame,
// `frame,id,x,y,w,h,confidence,-1,-1,-1`, frames numbered from 1 after the source frame they came
// from, as MOT's img1/000001.jpg; `jointflow-eval --mot-gt` scores it.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

#include "jointflowmeta.h"

namespace jointflow::cli {

class MotOutput {
 public:
  /// Opens `file` for writing; throws jointflow::Error when it cannot.
  explicit MotOutput(const std::string& file);
  /// The people of source frame `index` (from 0; meta may be null: nobody), every person of the
  /// meta, tentative ones too, as --output-json lists them. Each line is flushed, so a reader can
  /// follow a live run.
  void addFrame(std::int64_t index, const GstJointFlowMeta* meta);

 private:
  std::ofstream out_;
  std::string file_;
};

}  // namespace jointflow::cli
