#include "sample_summary.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace sodaevo {
namespace {

/// P(|T| < t) for Student's t with integer df: the finite series in
/// theta = atan(t / sqrt(df)) (odd df: 2/pi (theta + sin cos (1 + 2/3 cos^2 + ...));
/// even df: sin (1 + cos^2 / 2 + 1*3 cos^4 / (2*4) + ...)).
double central_probability(double t, int df) {
  const double theta = std::atan(t / std::sqrt(static_cast<double>(df)));
  const double s = std::sin(theta), c2 = std::cos(theta) * std::cos(theta);
  if (df % 2 == 0) {
    double term = 1.0, sum = 1.0;
    for (int k = 2; k < df; k += 2) {
      term *= c2 * (k - 1) / k;
      sum += term;
    }
    return s * sum;
  }
  double inner = 0.0;
  if (df > 1) {
    double term = 1.0;
    inner = 1.0;
    for (int k = 3; k < df; k += 2) {
      term *= c2 * (k - 1) / k;
      inner += term;
    }
    inner *= s * std::cos(theta);
  }
  return 2.0 / 3.141592653589793 * (theta + inner);
}

} // namespace

double student_t_975(int df) {
  if (df < 1) throw std::invalid_argument("student_t_975: degrees of freedom must be >= 1");
  if (df > 100000) return 1.959963984540054; // the normal quantile: the series would be long, the difference < 1e-5
  double lo = 0.0, hi = 20.0; // t(0.975, 1) = 12.7
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = (lo + hi) / 2.0;
    (central_probability(mid, df) < 0.95 ? lo : hi) = mid;
  }
  return (lo + hi) / 2.0;
}

SampleSummary summarize_sample(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("summarize_sample: no values");
  SampleSummary s;
  s.n = static_cast<int>(values.size());
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / s.n;
  double squares = 0.0;
  for (double v : values) squares += (v - s.mean) * (v - s.mean);
  s.sd = s.n > 1 ? std::sqrt(squares / (s.n - 1)) : 0.0;
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  s.median = s.n % 2 == 1 ? values[s.n / 2] : (values[s.n / 2 - 1] + values[s.n / 2]) / 2.0;
  const double half = s.n > 1 ? student_t_975(s.n - 1) * s.sd * std::sqrt(1.0 + 1.0 / s.n) : 0.0;
  s.interval95_low = s.mean - half;
  s.interval95_high = s.mean + half;
  return s;
}

} // namespace sodaevo
