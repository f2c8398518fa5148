#include "average_precision.hpp"

#include <algorithm>
#include <numeric>

namespace jointflow::eval {

double averagePrecision(const std::vector<ScoredJoint>& detections, int num_positives) {
  const std::size_t n = detections.size();
  if (n == 0) return 0.0;
  // Ascending stable sort reversed: highest score first, ties in reverse input order, which is
  // what numpy's argsort()[::-1] gives for the small arrays where its sort is stable.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return detections[a].score < detections[b].score;
  });
  std::reverse(order.begin(), order.end());

  // Recall/precision after each detection; padded with (0, 0) before and (1, 0) after.
  std::vector<double> rec(n + 2, 0.0), prec(n + 2, 0.0);
  int true_pos = 0;
  for (std::size_t k = 0; k < n; ++k) {
    true_pos += detections[order[k]].matched ? 1 : 0;
    rec[k + 1] = static_cast<double>(true_pos) / num_positives;  // 0/0 = NaN, as in poseval
    prec[k + 1] = static_cast<double>(true_pos) / static_cast<double>(k + 1);
  }
  rec[n + 1] = 1.0;
  for (std::size_t i = n + 1; i-- > 0;) prec[i] = std::max(prec[i], prec[i + 1]);  // monotone

  double ap = 0.0;
  for (std::size_t i = 1; i <= n + 1; ++i) {
    if (!(rec[i] == rec[i - 1])) ap += (rec[i] - rec[i - 1]) * prec[i];
  }
  return ap;
}

}  // namespace jointflow::eval
