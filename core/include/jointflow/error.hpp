// The one exception type the core throws for bad input (models, images, settings, files).
// Its message names the thing at fault and what was expected, so that callers (the GStreamer
// element, the command line tools) can show it to a user as it is.
#pragma once

#include <stdexcept>
#include <string>

namespace jointflow {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace jointflow
