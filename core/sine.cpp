// The engine's scalar sine (sine.hpp says what and why): HotSpot's x86-64 Math.sin,
// one operation per line in the routine's order. Its machine code evaluates some
// steps two lanes at a time (a "sin" and a "cos" lane of the polynomial); each lane
// is one line here. The vector kernel (detail/java_sine_simd.hpp) is the same
// sequence over several arguments; the tests hold both to the JVM's bits.
#include "sine.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "java_sine_large.hpp"
#include "java_sine_table.hpp"

namespace soda {
namespace {

using namespace java_sine;

/// The main path, 2^-252 <= |x| < 90112 (kReduced false); also the end of the
/// large-argument path (kReduced true), which enters it with x reduced by pi/4 to
/// x + tail and `rows` added to N for the table.
template <bool kReduced>
double main_path(double x, double tail = 0.0, unsigned rows = 0) {
  // 1. Reduction: N = (int)(x*32/pi + copysign(0.5, x)), truncated; r = x - N*pi/32
  // in three parts, and c, the part of the reduction r leaves out.
  const double y = x * kThirtyTwoOverPi;
  const int n = static_cast<int>(y + std::copysign(0.5, x));
  const double nd = static_cast<double>(n);
  const double m1 = nd * kPiOver32Part1;
  const double m2 = nd * kPiOver32Part2;
  const double m3 = nd * kPiOver32Part3;
  const double r1 = x - m1;
  const double r = r1 - m2;
  const double c1 = r1 - r;
  const double c2 = c1 - m2;
  const double minus_c = kReduced ? (m3 - c2) - tail : m3 - c2;
  const TableRow& t = kTable.row[kReduced ? (static_cast<unsigned>(n) + rows) & 63u : static_cast<unsigned>(n) & 63u];

  // 2. Polynomial, both lanes: psc4 = SC4*r1, msc4 = psc4*r, psc3 = SC3 + msc4,
  // psc1 = SC1 + SC2*r^2, sincospols = psc1 + psc3*r^4.
  const double r2 = r * r;
  const double r4 = r2 * r2;
  const double sigma_plus_cos = t.cos_minus_sigma + t.sigma; // cos(B)
  const double sin_weight = (sigma_plus_cos * r) * r2;       // cos(B) r^3
  const double cos_weight = t.sin_high * r2;                 // sin(B) r^2
  const double psc3_sin = (kSc4Sin * r1) * r + kSc3Sin;
  const double psc3_cos = (kSc4Cos * r1) * r + kSc3Cos;
  const double psc1_sin = kSc2Sin * r2 + kSc1Sin;
  const double psc1_cos = kSc2Cos * r2 + kSc1Cos;
  const double pols_sin = (psc1_sin + psc3_sin * r4) * sin_weight;
  const double pols_cos = (psc1_cos + psc3_cos * r4) * cos_weight;

  // 3. Correction for c: corr = -c * (S_hi*r - cos(B)) + S_lo.
  const double corr = minus_c * (t.sin_high * r - sigma_plus_cos) + t.sin_low;

  // 4. Two compensated sums: res_hi = (S_hi + sigma*r) + (cos(B) - sigma)*r, with
  // the rounding errors k_2 and k_3 of each sum kept.
  const double rs = t.sigma * r;
  const double med = r * t.cos_minus_sigma;
  const double res_int = rs + t.sin_high;
  const double res_hi = med + res_int;
  const double k2 = (t.sin_high - res_int) + rs;
  const double k3 = (res_int - res_hi) + med;

  // 5. The small parts, in the routine's order, then the whole.
  const double res_lo = (((corr + k2) + k3) + pols_sin) + pols_cos;
  return res_hi + res_lo;
}

} // namespace

double sine(double x) {
  const double ax = std::fabs(x);
  if (ax >= kMainPathLow && ax < kMainPathEnd) return main_path<false>(x);
  if (ax < kMainPathLow) return x; // the routine's tiny-argument paths give x back
  const std::uint64_t b = std::bit_cast<std::uint64_t>(x);
  if (std::isinf(x)) return std::bit_cast<double>(std::uint64_t{0xfff8000000000000}); // x * -0.0 on x86
  if (std::isnan(x)) return std::bit_cast<double>(b | 0x0008000000000000); // quieted
  const LargeReduction r = reduce_large(x);
  return main_path<true>(r.high, r.low, r.rows);
}

} // namespace soda
