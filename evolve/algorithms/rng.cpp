#include "rng.hpp"

#include <cmath>
#include <limits>

#include "core/sine.hpp"

namespace sodaevo {

namespace {
constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
}


Rng Rng::stream(std::uint64_t seed, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  std::uint64_t h = mix64(seed + kGolden);
  h = mix64(h ^ (a + 0x632BE59BD9B4E019ull));
  h = mix64(h ^ (b + 0x8CB92BA72F3D8DD7ull));
  h = mix64(h ^ (c + 0xA0761D6478BD642Full));
  return Rng(h);
}

std::uint64_t Rng::next_u64() { return mix64(state_ += kGolden); }

double Rng::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
  // Rejection of the short top range keeps every value equally likely.
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  for (;;) {
    const std::uint64_t r = next_u64();
    if (r < limit) return r % n;
  }
}

int Rng::between(int lo, int hi) {
  return lo + static_cast<int>(below(static_cast<std::uint64_t>(static_cast<long long>(hi) - lo + 1)));
}

double Rng::normal() {
  // 1 - uniform() is in (0, 1], so the log is finite. The sine of a uniform angle
  // is as good as the cosine, and the engine has its own.
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  return std::sqrt(-2.0 * portable_log(u1)) * soda::sine(6.283185307179586 * u2);
}

double portable_log(double x) {
  if (!(x > 0.0) || !std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
  int e = 0;
  double m = std::frexp(x, &e); // exact: x = m 2^e, m in [0.5, 1)
  if (m < 0.70710678118654752) {
    m *= 2.0; // exact
    --e;
  }
  // |s| <= 0.1716, s^2 <= 0.0295: the series' terms after s^23 / 23 are below
  // 2^-53 of the sum.
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double tail = 1.0 / 23.0;
  for (int k = 21; k >= 3; k -= 2) tail = 1.0 / k + s2 * tail;
  const double log_m = 2.0 * s + 2.0 * s * (s2 * tail);
  // ln 2 in two parts; e * kLn2High is exact for |e| < 2^11.
  constexpr double kLn2High = 0x1.62e42fee00000p-1;
  constexpr double kLn2Low = 0x1.a39ef35793c76p-33;
  const double fe = static_cast<double>(e);
  return fe * kLn2High + (log_m + fe * kLn2Low);
}

} // namespace sodaevo
