// A sample of replica results summarised: n, mean, median, sd, min, max and the
// 95 % prediction interval for one more replica.
//
// Why a prediction interval: the question a replica ensemble answers is "how far
// will this creature walk on another machine's sine" (core/sine_jitter.hpp), one
// new run, not "where is the mean": mean +- t(0.975, n-1) * sd * sqrt(1 + 1/n)
// holds a new draw 95 % of the time when the runs are roughly normal.
#pragma once

#include <vector>

namespace sodaevo {

struct SampleSummary {
  int n = 0;
  double mean = 0.0;
  double median = 0.0;
  double sd = 0.0; ///< sample standard deviation (n - 1); 0 for n = 1
  double min = 0.0;
  double max = 0.0;
  /// mean -+ t(0.975, n - 1) * sd * sqrt(1 + 1/n); [mean, mean] for n = 1 (no spread known).
  double interval95_low = 0.0;
  double interval95_high = 0.0;
};

/// Half the width of the 95 % prediction interval of n runs with sample standard
/// deviation sd: t(0.975, n - 1) * sd * sqrt(1 + 1/n); 0 for n <= 1.
double prediction_half_width95(int n, double sd);

/// The summary of `values` (at least one; throws std::invalid_argument if empty).
SampleSummary summarize_sample(std::vector<double> values);

/// The 0.975 quantile of Student's t with `degrees_of_freedom` >= 1 (12.706 for 1,
/// tending to 1.95996 for many); the same bits on every machine.
double student_t_975(int degrees_of_freedom);

} // namespace sodaevo
