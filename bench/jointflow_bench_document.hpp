// jointflow-bench's writer: the figures its cases gathered (jointflow_bench_cases.hpp) as the
// Markdown document (docs/benchmarks.md), each table with the prose that says how it was measured.
#pragma once

#include <string>

#include "jointflow_bench_cases.hpp"

namespace jointflow::bench {

/// `minutes`: the run's wall time; `load_before`: the load average before its first case.
std::string budgetMarkdown(const BudgetSettings& settings, const BudgetFigures& figures,
                           double minutes, const std::string& load_before);

}  // namespace jointflow::bench
