// The order statistics every metric and study uses, in one place: a percentile is the nearest-rank value
// (index round(q (n - 1)) of the sorted values), so p99 of 1..100 is 99; the median of an even count is the
// mean of the middle two.
#pragma once

#include <algorithm>
#include <vector>

namespace marchcheck::validation {

// q in [0, 1]; 0 for no values.
inline double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double rank = q * static_cast<double>(values.size() - 1) + 0.5;
  return values[std::min(values.size() - 1, static_cast<size_t>(rank))];
}

// 0 for no values.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace marchcheck::validation
