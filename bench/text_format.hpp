// Numbers as the benchmarks' documents print them. Header-only: the benchmarks and the bench
// library share it.
#pragma once

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace jointflow::bench {

/// `v` with `digits` decimals; "n/a" for NaN (a figure that could not be had).
inline std::string fixed(double v, int digits) {
  if (std::isnan(v)) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace jointflow::bench
