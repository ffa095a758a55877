// The engine's scalar sine (sine.hpp says what and why). The operations and the
// fused ones are those of the vector kernel (detail/glibc_sine.hpp), one lane at a time
// and taking only its own branch.
#include "sine.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "sine_table.hpp"

namespace soda {
namespace {

using namespace glibc_sine;

/// The table row nearest |a| (i/128, exact) and its index.
[[gnu::always_inline]] inline double table_point(double abs_a, int& row) {
  const double point = (abs_a + kBig) - kBig;
  row = static_cast<int>(point * 128.0);
  return point;
}

/// glibc's do_sin(a, da): the Taylor polynomial for |a| < 0.126, else the table
/// row nearest |a| and short polynomials in the distance to it.
[[gnu::always_inline]] inline double do_sin(double a, double da) {
  const double abs_a = std::fabs(a);
  if (abs_a < kTaylorBound) { // a + ((P(a^2)*a - da/2)*a^2 + da)
    const double aa = a * a;
    double p = std::fma(aa, kS5, kS4);
    p = std::fma(aa, p, kS3);
    p = std::fma(aa, p, kS2);
    p = std::fma(aa, p, kS1);
    return a + std::fma(aa, std::fma(p, a, -(da * 0.5)), da);
  }
  int row = 0;
  const double point = table_point(abs_a, row);
  const double dx = a <= 0.0 ? -da : da;
  const double xr = abs_a - point;
  const double xx = xr * xr;
  const double p1 = std::fma(xx, kSn5, kSn3);
  const double p2 = std::fma(xx, std::fma(xx, kCs6, kCs4), kCs2);
  const double* r = glibc_table().row[row];
  const double sn = r[0], ssn = r[1], cs = r[2], ccs = r[3];
  // s = xr + (dx + xr^3 p1), c = xr*dx + xx*p2, cor = (ssn + s*ccs - sn*c) + cs*s.
  const double s = xr + std::fma(xr * xx, p1, dx);
  const double c = std::fma(xr, dx, xx * p2);
  const double cor = std::fma(s, cs, std::fma(-c, sn, std::fma(s, ccs, ssn)));
  return std::copysign(sn + cor, a);
}

/// glibc's do_cos(a, da): cos(a + da) from the table row nearest |a|.
[[gnu::always_inline]] inline double do_cos(double a, double da) {
  const double abs_a = std::fabs(a);
  int row = 0;
  const double point = table_point(abs_a, row);
  const double dx = a < 0.0 ? -da : da;
  const double xr = (abs_a - point) + dx;
  const double xx = xr * xr;
  const double p1 = std::fma(xx, kSn5, kSn3);
  const double p2 = std::fma(xx, std::fma(xx, kCs6, kCs4), kCs2);
  const double* r = glibc_table().row[row];
  const double sn = r[0], ssn = r[1], cs = r[2], ccs = r[3];
  // s = xr + xr^3 p1, c = xx*p2, cor = (ccs - s*ssn - cs*c) - sn*s.
  const double s = std::fma(xr * xx, p1, xr);
  const double c = xx * p2;
  const double cor = std::fma(-s, sn, std::fma(-c, cs, std::fma(-s, ssn, ccs)));
  return cs + cor;
}

[[gnu::always_inline]] inline double sine_kernel(double x) {
  const double ax = std::fabs(x);
  if (!(ax < kReduceBound)) return std::numeric_limits<double>::quiet_NaN(); // sine.hpp: Range
  if (ax < kTinyBound) return x;
  if (ax < kSinBound) return do_sin(x, 0.0);
  if (ax < kCosBound) return std::copysign(do_cos(kHalfPiHigh - ax, kHalfPiLow), x);
  // reduce_sincos: n = round(x * 2/pi), x - n*pi/2 in four parts as b + db.
  const double tn = std::fma(x, kHalfPiInverse, kToInt);
  const double xn = tn - kToInt;
  double y = std::fma(-xn, kHalfPi1, x);
  y = std::fma(-xn, kHalfPi2, y);
  const double t2 = std::fma(-xn, kHalfPi3, y);
  double db = std::fma(-kHalfPi3, xn, y - t2);
  const double b = std::fma(-xn, kHalfPi4, t2);
  db = db + std::fma(-xn, kHalfPi4, t2 - b);
  const std::uint64_t n = std::bit_cast<std::uint64_t>(tn); // the quadrant in its low bits
  const double r = (n & 1) != 0 ? do_cos(b, db) : do_sin(b, db);
  return (n & 2) != 0 ? -r : r;
}

#if defined(__x86_64__) && defined(__GNUC__)
// With the instruction, std::fma is one vfmadd; without, a correctly rounded
// library call. Same bits, several times the speed.
[[gnu::target("fma")]] double sine_with_fma_instructions(double x) { return sine_kernel(x); }

bool cpu_has_fma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("fma");
}
#endif

} // namespace

double detail::sine_portable(double x) { return sine_kernel(x); }

double sine(double x) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool fma = cpu_has_fma();
  if (fma) return sine_with_fma_instructions(x);
#endif
  return sine_kernel(x);
}

double sine_range_end() { return std::nextafter(kReduceBound, 0.0); }

} // namespace soda
