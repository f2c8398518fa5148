// identity-bench's writer: the figures its cases gathered (identity_cases.hpp) as the Markdown
// document (docs/identity.md) and the JSON of the raw figures (docs/identity.json). Apart from
// the cases so that a case says what it measures and the writer how it is shown.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "identity_cases.hpp"

namespace jointflow::bench {

/// What the document says about the run besides its figures.
struct IdentityRunInfo {
  std::string command;                  ///< the command line that makes these figures again
  std::string model;                    ///< the spatial model, as toString(ModelType) names it
  std::string input_size;               ///< its input size
  std::string json_name;                ///< the JSON file's name, which the document points to
  double seconds = 0;                   ///< the run's wall time
  double load_start = 0, load_end = 0;  ///< the 1-minute load average at its start and end
};

nlohmann::json identityJson(const IdentityFigures& figures, const IdentityOptions& options,
                            const IdentityRunInfo& info);

std::string identityMarkdown(const IdentityFigures& figures, const IdentityOptions& options,
                             const IdentityRunInfo& info);

}  // namespace jointflow::bench
