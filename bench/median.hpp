// The median of a set of timings or errors, as the benchmarks report them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace sodaevo::bench {

/// Median of v (the mean of the two middle values for an even count); 0 for none.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace sodaevo::bench
