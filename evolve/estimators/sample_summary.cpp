#include "sample_summary.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace sodaevo {
namespace {

// t(0.975, df) for df = 1..30, to double precision (the root of the regularised
// incomplete beta function, computed with 40 digits). Literals and, beyond,
// plain arithmetic: the quantile, and so every interval, has the same bits on
// every machine (no libm function whose last bit differs between libraries).
constexpr double kT975[30] = {
    12.706204736174705, 4.302652729749464,  3.1824463052837095, 2.7764451051977943, 2.5705818356363155,
    2.44691185114497,   2.3646242515927853, 2.3060041352041667, 2.2621571627982053, 2.228138851986275,
    2.2009851600916397, 2.178812829667229,  2.1603686564627926, 2.144786687917804,  2.1314495455597755,
    2.1199052992212546, 2.109815577833317,  2.1009220402410387, 2.0930240544083096, 2.085963447265865,
    2.0796138447276804, 2.0738730679040263, 2.0686576104190486, 2.063898561628026,  2.0595385527532977,
    2.055529438642873,  2.0518305164802855, 2.048407141795245,  2.0452296421327043, 2.042272456301238};

constexpr double kZ975 = 1.9599639845400543; // the normal distribution's 0.975 quantile

} // namespace

double student_t_975(int df) {
  if (df < 1) throw std::invalid_argument("student_t_975: degrees of freedom must be >= 1");
  if (df <= 30) return kT975[df - 1];
  // Cornish-Fisher expansion in 1/df (off by less than 3e-8 from df = 31 on).
  const double z = kZ975, z2 = z * z, v = static_cast<double>(df);
  const double g1 = (z2 + 1.0) * z / 4.0;
  const double g2 = ((5.0 * z2 + 16.0) * z2 + 3.0) * z / 96.0;
  const double g3 = (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) * z / 384.0;
  const double g4 = ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) * z / 92160.0;
  return z + (g1 + (g2 + (g3 + g4 / v) / v) / v) / v;
}

double prediction_half_width95(int n, double sd) {
  return n > 1 ? student_t_975(n - 1) * sd * std::sqrt(1.0 + 1.0 / n) : 0.0;
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
  const double half = prediction_half_width95(s.n, s.sd);
  s.interval95_low = s.mean - half;
  s.interval95_high = s.mean + half;
  return s;
}

} // namespace sodaevo
