// RunningEstimate: n, mean and standard deviation of a score over replicas,
// gathered a few at a time (Welford's update for one value, Chan et al.'s
// pairwise update for a batch summarised by its count, mean and sd).
//
// Why not keep the values: an elite may gather replicas over a whole run, and the
// three numbers are all the archive compares. The updates round, so the result
// depends on the order of the batches: a run adds them in replica-index order,
// in batches its insertion rule fixes, which keeps results identical on every
// thread and rank count.
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
  /// Adds a batch of `count` >= 1 values with mean `batch_mean` and sample
  /// standard deviation `batch_sd`.
  void merge(long long count, double batch_mean, double batch_sd) {
    const double batch_m2 = batch_sd * batch_sd * static_cast<double>(count - 1);
    if (n == 0) { // the batch itself, exactly
      n = count;
      mean = batch_mean;
      m2 = batch_m2;
      return;
    }
    const double na = static_cast<double>(n), nb = static_cast<double>(count);
    const double delta = batch_mean - mean;
    n += count;
    const double total = static_cast<double>(n);
    mean += delta * nb / total;
    m2 += batch_m2 + delta * delta * na * nb / total;
  }
  /// Sample standard deviation (0 for fewer than 2 values).
  [[nodiscard]] double sd() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }

  bool operator==(const RunningEstimate&) const = default;
};

} // namespace sodaevo
