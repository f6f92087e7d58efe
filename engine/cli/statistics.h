#pragma once
// Statistics of per-frame timings.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace ivgi::cli {

// The q-quantile (0.5: median, 0.9: p90) with linear interpolation between order statistics.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  double at = q * double(values.size() - 1);
  size_t lo = size_t(std::floor(at)), hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (at - double(lo));
}

// The mean (0 of none): where frames differ in kind (ar's restarts among chained frames), the
// animation's rate is the mean's, not the median's.
inline double mean(const std::vector<double>& values) {
  return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

}  // namespace ivgi::cli
