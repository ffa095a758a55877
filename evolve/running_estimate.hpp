// RunningEstimate: n, mean and standard deviation of a score over replicas,
// gathered a few at a time (Welford's update).
//
// Why not keep the values: an elite may gather replicas over a whole run, and the
// three numbers are all the archive compares. The update rounds, so its result
// depends on the order of the values: a run adds replicas in replica-index order,
// which keeps results identical on every thread count.
#pragma once

#include <cmath>

namespace sodaevo {

struct RunningEstimate {
  long long n = 0;
  double mean = 0.0;
  double m2 = 0.0; ///< sum of squared deviations from the mean

  /// Adds one value.
  void add(double value) {
    ++n;
    const double delta = value - mean;
    mean += delta / static_cast<double>(n);
    m2 += delta * (value - mean);
  }
  /// Sample standard deviation (0 for fewer than 2 values).
  [[nodiscard]] double sd() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }

  bool operator==(const RunningEstimate&) const = default;
};

} // namespace sodaevo
