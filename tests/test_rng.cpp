// The GA's random numbers without the C library's rounding: portable_log against
// the C library's log (the reference: correctly rounded or nearly), and the normal
// draw's distribution.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "evolve/algorithms/rng.hpp"

using namespace sodaevo;

namespace {

/// Distance in units in the last place between two positive finite doubles.
std::int64_t ulps_apart(double a, double b) {
  std::int64_t ia = 0, ib = 0;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return ia > ib ? ia - ib : ib - ia;
}

/// |portable_log(x) - log(x)| in ulps of log(x) (for log(x) != 0).
std::int64_t log_error(double x) {
  const double mine = portable_log(x), ref = std::log(x);
  if (ref == 0.0) return mine == 0.0 ? 0 : 1'000'000;
  if ((mine < 0.0) != (ref < 0.0)) return 1'000'000;
  return ulps_apart(std::fabs(mine), std::fabs(ref));
}

} // namespace

TEST_CASE("portable_log is within 2 ulp of the C library's log", "[rng]") {
  std::int64_t worst = 0;
  double worst_x = 0.0;
  auto probe = [&](double x) {
    const std::int64_t e = log_error(x);
    if (e > worst) {
      worst = e;
      worst_x = x;
    }
  };
  // The GA's arguments: 1 - uniform(), in (0, 1].
  Rng rng(12345);
  for (int i = 0; i < 1'000'000; ++i) probe(1.0 - rng.uniform());
  // Near 1 (where log is small and the reduction must not lose it), near the
  // reduction's switch at sqrt(1/2), powers of two, and far out.
  for (int k = 1; k < 2000; ++k) {
    probe(1.0 + k * std::numeric_limits<double>::epsilon());
    probe(1.0 - k * std::numeric_limits<double>::epsilon() / 2);
    probe(0.70710678118654752 + (k - 1000) * 1e-16);
    probe(1.41421356237309505 + (k - 1000) * 2e-16);
  }
  for (int e = -1070; e <= 1020; ++e) {
    probe(std::ldexp(1.0, e));
    probe(std::ldexp(1.7, e));
  }
  for (int i = 0; i < 100'000; ++i) probe(std::ldexp(0.5 + rng.uniform(), static_cast<int>(rng.below(2000)) - 1000));
  INFO("worst at x = " << worst_x);
  CHECK(worst <= 2);
  CHECK(portable_log(1.0) == 0.0);
  CHECK(std::isnan(portable_log(0.0)));
  CHECK(std::isnan(portable_log(-1.0)));
  CHECK(std::isnan(portable_log(std::numeric_limits<double>::infinity())));
  CHECK(std::isnan(portable_log(std::numeric_limits<double>::quiet_NaN())));
}

TEST_CASE("Rng::normal draws a standard normal", "[rng]") {
  Rng rng = Rng::stream(7, 1, 2, 3);
  const int n = 400'000;
  double sum = 0.0, squares = 0.0, fourth = 0.0;
  int beyond_196 = 0, beyond_3 = 0, not_finite = 0;
  for (int i = 0; i < n; ++i) {
    const double z = rng.normal();
    not_finite += !std::isfinite(z);
    sum += z;
    squares += z * z;
    fourth += z * z * z * z;
    beyond_196 += std::fabs(z) > 1.959963984540054;
    beyond_3 += std::fabs(z) > 3.0;
  }
  // Standard errors for n = 400,000: mean 0.0016, variance 0.0022, kurtosis ~0.02,
  // share beyond 1.96 0.00034, beyond 3 0.00008: bounds of about 5 of them.
  CHECK(not_finite == 0);
  CHECK(std::fabs(sum / n) < 0.008);
  CHECK(std::fabs(squares / n - 1.0) < 0.011);
  CHECK(std::fabs(fourth / n - 3.0) < 0.1);
  CHECK(std::fabs(static_cast<double>(beyond_196) / n - 0.05) < 0.0017);
  CHECK(std::fabs(static_cast<double>(beyond_3) / n - 0.0026998) < 0.0004);
}
