#include "exact_sines.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "simd_ops.hpp"

namespace soda {
namespace {

using simd::Avx2Ops;
using simd::Avx512Ops;
using simd::kMaxWidth;

// ---------------------------------------------------------------------------
// glibc's table: sin(i/128) and cos(i/128), i = 0..109, each as a high double and
// a low double (row: sin high, sin low, cos high, cos low).
//
// The high parts are the nearest doubles; the low parts are the nearest doubles to
// the rest, except in 18 places where glibc's table (__sincostab) is 1, 2 or 39
// units of the last place off that (compared with a dump of glibc 2.36's
// __sincostab). We compute the nearest values from a 256-bit fixed-point Taylor
// series and apply those 18 offsets; the self-check and the tests compare the
// whole sine with std::sin.
// ---------------------------------------------------------------------------

constexpr int kTableRows = 110;
struct GlibcTable {
  alignas(64) double row[kTableRows][4];
};

// Unsigned fixed point: limb 0 is the integer part, limbs 1-4 the fraction, most
// significant first.
constexpr int kLimbs = 5;
struct Fixed {
  std::uint64_t w[kLimbs] = {};
};
__extension__ typedef unsigned __int128 Wide; // GCC and Clang on x86-64

void add(Fixed& a, const Fixed& b) {
  Wide carry = 0;
  for (int j = kLimbs - 1; j >= 0; --j) {
    const Wide s = static_cast<Wide>(a.w[j]) + b.w[j] + carry;
    a.w[j] = static_cast<std::uint64_t>(s);
    carry = s >> 64;
  }
}
void subtract(Fixed& a, const Fixed& b) { // a >= b
  bool borrow = false;
  for (int j = kLimbs - 1; j >= 0; --j) {
    const std::uint64_t d = a.w[j] - b.w[j] - (borrow ? 1 : 0);
    borrow = a.w[j] < b.w[j] || (a.w[j] == b.w[j] && borrow);
    a.w[j] = d;
  }
}
void multiply(Fixed& a, std::uint64_t m) {
  Wide carry = 0;
  for (int j = kLimbs - 1; j >= 0; --j) {
    const Wide p = static_cast<Wide>(a.w[j]) * m + carry;
    a.w[j] = static_cast<std::uint64_t>(p);
    carry = p >> 64;
  }
}
void divide(Fixed& a, std::uint64_t d) { // truncates: the series loses < 2^-250
  Wide rest = 0;
  for (int j = 0; j < kLimbs; ++j) {
    const Wide cur = (rest << 64) | a.w[j];
    a.w[j] = static_cast<std::uint64_t>(cur / d);
    rest = cur % d;
  }
}
bool is_zero(const Fixed& a) {
  return std::all_of(a.w, a.w + kLimbs, [](std::uint64_t v) { return v == 0; });
}
bool less(const Fixed& a, const Fixed& b) {
  for (int j = 0; j < kLimbs; ++j) {
    if (a.w[j] != b.w[j]) return a.w[j] < b.w[j];
  }
  return false;
}
// Bit i counted from the top: its value is 2^(63 - i).
unsigned bit(const Fixed& a, int i) {
  return i >= 64 * kLimbs ? 0u : static_cast<unsigned>(a.w[i / 64] >> (63 - i % 64)) & 1u;
}
/// The nearest double (ties to even).
double nearest(const Fixed& a) {
  int top = -1;
  for (int j = 0; j < kLimbs && top < 0; ++j) {
    if (a.w[j] != 0) top = 64 * j + std::countl_zero(a.w[j]);
  }
  if (top < 0) return 0.0;
  std::uint64_t m = 0;
  for (int i = top; i < top + 53; ++i) m = m << 1 | bit(a, i);
  bool sticky = false;
  for (int i = top + 54; i < 64 * kLimbs && !sticky; ++i) sticky = bit(a, i) != 0;
  if (bit(a, top + 53) != 0 && (sticky || (m & 1) != 0)) ++m;
  return std::ldexp(static_cast<double>(m), 63 - (top + 52));
}
/// A double >= 0 whose bits all fall within the fixed point, exactly.
Fixed exactly(double v) {
  Fixed f;
  int e = 0;
  const auto m = static_cast<std::uint64_t>(std::ldexp(std::frexp(v, &e), 53)); // v = m * 2^(e - 53)
  for (int b = 0; b < 53; ++b) {
    if ((m >> b & 1) == 0) continue;
    const int i = 63 - (e - 53 + b);
    f.w[i / 64] |= std::uint64_t{1} << (63 - i % 64);
  }
  return f;
}
/// v as nearest high double + nearest double to the rest.
void split(const Fixed& v, double* high_low) {
  const double high = nearest(v);
  const Fixed h = exactly(high);
  Fixed rest = v;
  double low = 0.0;
  if (less(v, h)) {
    rest = h;
    subtract(rest, v);
    low = -nearest(rest);
  } else {
    subtract(rest, h);
    low = nearest(rest);
  }
  high_low[0] = high;
  high_low[1] = low;
}

struct TableOffset {
  int row, column;
  std::int64_t ulps; ///< glibc's value minus the nearest, in units of the last place
};
constexpr TableOffset kGlibcOffsets[] = {
    {2, 1, 1},   {10, 1, 1}, {23, 1, 39}, {26, 3, 1}, {27, 1, 1}, {33, 1, 1},  {34, 1, 1}, {36, 1, 1},  {40, 1, -2},
    {44, 3, 1},  {70, 3, 1}, {75, 1, 1},  {75, 3, -2}, {79, 3, 1}, {85, 1, 1}, {90, 1, -2}, {94, 1, 1}, {107, 1, 1}};

GlibcTable build_glibc_table() {
  GlibcTable t{};
  for (int i = 0; i < kTableRows; ++i) {
    // sin and cos of i/128 from their series; the terms x^k/k! come one from the
    // other (times i, divided by 128 k), summed by sign.
    Fixed sin_plus, sin_minus, cos_plus, cos_minus, term;
    term.w[0] = 1;
    cos_plus = term;
    for (int k = 1; !is_zero(term); ++k) {
      multiply(term, static_cast<std::uint64_t>(i));
      divide(term, 128 * static_cast<std::uint64_t>(k));
      Fixed* sums[4] = {&cos_plus, &sin_plus, &cos_minus, &sin_minus};
      add(*sums[k % 4], term);
    }
    subtract(sin_plus, sin_minus);
    subtract(cos_plus, cos_minus);
    split(sin_plus, &t.row[i][0]);
    split(cos_plus, &t.row[i][2]);
  }
  for (const TableOffset& o : kGlibcOffsets) {
    double& v = t.row[o.row][o.column];
    v = std::bit_cast<double>(std::bit_cast<std::int64_t>(v) + o.ulps);
  }
  return t;
}

const GlibcTable& glibc_table() {
  static const GlibcTable table = build_glibc_table();
  return table;
}

// ---------------------------------------------------------------------------
// glibc's sin, W lanes at a time. Its branches by |x| (s_sin.c):
//   |x| < 2^-26                  x
//   |x| < 0.85546875             do_sin(x, 0)
//   |x| < 2.426265 (0x400368fd)  copysign(do_cos(pi/2 - |x|, pi/2 low), x)
//   |x| < 105414350 (0x419921fb) x reduced by pi/2 to (a, da) and quadrant n:
//                                do_sin(a, da) or do_cos(a, da) by n's parity,
//                                negated when n & 2
// and do_sin switches to a Taylor polynomial for |a| < 0.126. Every lane takes
// every branch here and keeps its own; the operations, and which of them are
// fused (the FMA build's choice, read from its machine code), are glibc's.
// ---------------------------------------------------------------------------

double from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

// glibc's constants (s_sin.c, usncs.h), by their bits.
const double kTinyBound = 0x1p-26;
const double kSinBound = from_bits(0x3feb600000000000);    // 0.85546875
const double kCosBound = from_bits(0x400368fd00000000);    // 2.426265...
const double kReduceBound = from_bits(0x419921fb00000000); // 105414350
const double kTaylorBound = 0.126;
const double kBig = from_bits(0x42c8000000000000); // 1.5 * 2^45: adding it rounds to 1/128
const double kToInt = from_bits(0x4338000000000000);
const double kHalfPiInverse = from_bits(0x3fe45f306dc9c883);
const double kHalfPi1 = from_bits(0x3ff921fb58000000), kHalfPi2 = from_bits(0xbe4dde973c000000);
const double kHalfPi3 = from_bits(0xbc8cb3b398000000), kHalfPi4 = from_bits(0xbacd747f23e32ed7);
const double kHalfPiHigh = from_bits(0x3ff921fb54442d18), kHalfPiLow = from_bits(0x3c91a62633145c07);
const double kSn3 = from_bits(0xbfc5555555555515), kSn5 = from_bits(0x3f811110e829872f);
const double kCs2 = 0.5, kCs4 = from_bits(0xbfa5555555555535), kCs6 = from_bits(0x3f56c16bedd9e239);
const double kS1 = from_bits(0xbfc5555555555555), kS2 = from_bits(0x3f81111111110ece);
const double kS3 = from_bits(0xbf2a01a019db08b8), kS4 = from_bits(0x3ec71de27b9a7ed9);
const double kS5 = from_bits(0xbe5addffc2fcdf59);

/// N vectors of sines at once: in[0, N*W) to out, each step written for all N
/// vectors before the next, so that the processor sees N independent chains side
/// by side (one vector's chain, from the reduction through the table to the
/// polynomials, is longer than the reorder window can cover with one vector's
/// instructions). rest[k] marks the lanes of vector k that must call std::sin
/// (|x| >= 105414350, infinities, NaN).
// GCC 12 takes the undefined pass-through operand of _mm512_cvttpd_epi32 and
// _mm512_insertf64x4 (in O::to_i32 and O::gather_rows4) for an uninitialised
// variable once they are inlined here: a false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class O, int N>
void glibc_sin(const GlibcTable& t, const double* in, double* out, unsigned* rest) {
  using V = typename O::V;
  using M = typename O::M;
#define SODA_EACH _Pragma("GCC unroll 4") for (int k = 0; k < N; ++k)
  const V sign = O::set1(-0.0);
  const V zero = O::set1(0.0);
  V x[N], ax[N];
  M sin_branch[N], cos_branch[N], reduced[N], reducible[N];
  SODA_EACH {
    x[k] = O::loadu(in + k * O::W);
    ax[k] = O::abs(x[k]);
    sin_branch[k] = O::lt(ax[k], O::set1(kSinBound));
    const M below_cos_end = O::lt(ax[k], O::set1(kCosBound));
    reducible[k] = O::lt(ax[k], O::set1(kReduceBound)); // false for NaN
    cos_branch[k] = O::m_andnot(below_cos_end, sin_branch[k]);
    reduced[k] = O::m_andnot(reducible[k], below_cos_end);
  }

  // reduce_sincos: n = round(x * 2/pi), x - n*pi/2 in four parts as b + db.
  const V toint = O::set1(kToInt);
  V tn[N], xn[N], y[N];
  SODA_EACH tn[k] = O::fma(x[k], O::set1(kHalfPiInverse), toint);
  SODA_EACH xn[k] = O::sub(tn[k], toint);
  SODA_EACH y[k] = O::fnma(xn[k], O::set1(kHalfPi1), x[k]);
  SODA_EACH y[k] = O::fnma(xn[k], O::set1(kHalfPi2), y[k]);
  const V pp3 = O::set1(kHalfPi3), pp4 = O::set1(kHalfPi4);
  V t2[N], db[N], b[N];
  SODA_EACH t2[k] = O::fnma(xn[k], pp3, y[k]);
  SODA_EACH db[k] = O::fnma(pp3, xn[k], O::sub(y[k], t2[k]));
  SODA_EACH b[k] = O::fnma(xn[k], pp4, t2[k]);
  SODA_EACH db[k] = O::add(db[k], O::fnma(xn[k], pp4, O::sub(t2[k], b[k])));

  // Each lane's (a, da) and whether it takes do_cos.
  M use_cos[N], negate[N];
  V a[N], da[N], abs_a[N];
  SODA_EACH {
    const M odd = O::m_and(reduced[k], O::has_bit(tn[k], 1));
    negate[k] = O::m_and(reduced[k], O::has_bit(tn[k], 2));
    use_cos[k] = O::m_or(cos_branch[k], odd);
    a[k] = O::select(sin_branch[k], x[k],
                     O::select(cos_branch[k], O::sub(O::set1(kHalfPiHigh), ax[k]), O::select(reduced[k], b[k], zero)));
    da[k] = O::select(cos_branch[k], O::set1(kHalfPiLow), O::select(reduced[k], db[k], zero));
    abs_a[k] = O::abs(a[k]);
  }

  // do_sin and do_cos: the table row nearest |a|, and a short polynomial in the
  // distance xr to it. do_sin negates da when a <= 0, do_cos when a < 0.
  const V big = O::set1(kBig);
  V table_point[N];
  alignas(64) std::int32_t row[N][kMaxWidth];
  SODA_EACH {
    table_point[k] = O::sub(O::add(abs_a[k], big), big); // i/128, exact
    O::to_i32(O::mul(table_point[k], O::set1(128.0)), row[k]);
  }
  V cols[N][4];
  SODA_EACH O::gather_rows4(&t.row[0][0], row[k], cols[k]);

  // do_sin for |a| < 0.126: a + ((P(a^2)*a - da/2)*a^2 + da).
  V aa[N], p[N], taylor_result[N];
  SODA_EACH aa[k] = O::mul(a[k], a[k]);
  SODA_EACH p[k] = O::fma(aa[k], O::set1(kS5), O::set1(kS4));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS3));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS2));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS1));
  SODA_EACH taylor_result[k] = O::add(a[k], O::fma(aa[k], O::fms(p[k], a[k], O::mul(da[k], O::set1(0.5))), da[k]));

  V xr[N], xx[N], p1[N], xr_xx[N], c_cos[N];
  SODA_EACH {
    const M flip = O::m_or(O::m_and(use_cos[k], O::lt(a[k], zero)), O::m_andnot(O::le(a[k], zero), use_cos[k]));
    const V dx = O::select(flip, O::bits_xor(da[k], sign), da[k]);
    const V xr0 = O::sub(abs_a[k], table_point[k]);
    xr[k] = O::select(use_cos[k], O::add(xr0, dx), xr0);
    da[k] = dx;
  }
  SODA_EACH xx[k] = O::mul(xr[k], xr[k]);
  SODA_EACH {
    p1[k] = O::fma(xx[k], O::set1(kSn5), O::set1(kSn3));
    xr_xx[k] = O::mul(xr[k], xx[k]);
    const V p2 = O::fma(xx[k], O::fma(xx[k], O::set1(kCs6), O::set1(kCs4)), O::set1(kCs2));
    c_cos[k] = O::mul(xx[k], p2);
  }
  V sin_result[N], cos_result[N];
  SODA_EACH {
    const V sn = cols[k][0], ssn = cols[k][1], cs = cols[k][2], ccs = cols[k][3];
    const V dx = da[k];
    // do_sin: s = xr + (dx + xr^3 p1), c = xr*dx + xx*p2, cor = (ssn + s*ccs - sn*c) + cs*s.
    const V s_sin = O::add(xr[k], O::fma(xr_xx[k], p1[k], dx));
    const V c_sin = O::fma(xr[k], dx, c_cos[k]);
    const V cor_sin = O::fma(s_sin, cs, O::fnma(c_sin, sn, O::fma(s_sin, ccs, ssn)));
    sin_result[k] = O::bits_or(O::abs(O::add(sn, cor_sin)), O::bits_and(a[k], sign));
  }
  SODA_EACH {
    const V sn = cols[k][0], ssn = cols[k][1], cs = cols[k][2], ccs = cols[k][3];
    // do_cos: s = xr + xr^3 p1, c = xx*p2, cor = (ccs - s*ssn - cs*c) - sn*s.
    const V s_cos = O::fma(xr_xx[k], p1[k], xr[k]);
    const V cor_cos = O::fnma(s_cos, sn, O::fnma(c_cos[k], cs, O::fnma(s_cos, ssn, ccs)));
    cos_result[k] = O::add(cs, cor_cos);
  }
  SODA_EACH {
    const M taylor = O::m_andnot(O::lt(abs_a[k], O::set1(kTaylorBound)), use_cos[k]);
    V r = O::select(taylor, taylor_result[k], O::select(use_cos[k], cos_result[k], sin_result[k]));
    r = O::select(cos_branch[k], O::bits_or(O::abs(r), O::bits_and(x[k], sign)), r);
    r = O::select(negate[k], O::bits_xor(r, sign), r);
    r = O::select(O::lt(ax[k], O::set1(kTinyBound)), x[k], r);
    O::storeu(out + k * O::W, r);
    rest[k] = ((1u << O::W) - 1u) & ~O::lanes(reducible[k]);
  }
#undef SODA_EACH
}
#pragma GCC diagnostic pop

template <class O>
void vector_sines(const double* a, double* out, int n) {
  const GlibcTable& t = glibc_table();
  // Vector pass first, then the std::sin calls (a call inside the vector loop
  // would spill every vector register around it).
  constexpr int kChunk = 256;
  unsigned rest[kChunk / O::W];
  for (int base = 0; base < n; base += kChunk) {
    const int end = std::min(n, base + kChunk);
    // Two vectors at a time (the arrays are padded to a multiple of 8 lanes; a
    // vector past n computes the padding and is not read).
    int i = base;
    for (; i + O::W < end; i += 2 * O::W) glibc_sin<O, 2>(t, a + i, out + i, rest + (i - base) / O::W);
    if (i < end) glibc_sin<O, 1>(t, a + i, out + i, rest + (i - base) / O::W);
    for (int i = base; i < end; i += O::W) {
      for (unsigned r = rest[(i - base) / O::W]; r != 0; r &= r - 1) {
        const int l = std::countr_zero(r);
        if (i + l < n) out[i + l] = std::sin(a[i + l]);
      }
    }
  }
}

void scalar_sines(const double* a, double* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = std::sin(a[i]);
}

/// The vector sine against std::sin on arguments from every branch (muscle
/// arguments lie in (-2pi, 2pi)), their ends, and a few far ones.
template <class O>
bool self_check() {
  constexpr int kCount = 8192;
  std::vector<double> a(kCount), out(kCount);
  std::uint64_t seed = 0x5eed;
  for (int i = 0; i < kCount; ++i) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    const double u = static_cast<double>(seed >> 11) * 0x1p-53; // [0, 1)
    a[i] = i % 8 == 7 ? (u - 0.5) * 400.0 : (u - 0.5) * 16.0;
  }
  const double edges[] = {kTinyBound, kTaylorBound, kSinBound, kCosBound, 0.0, 1e-300};
  for (int e = 0; e < 6; ++e) {
    a[2 * e] = edges[e];
    a[2 * e + 1] = -std::nextafter(edges[e], 0.0);
  }
  vector_sines<O>(a.data(), out.data(), kCount);
  for (int i = 0; i < kCount; ++i) {
    if (std::bit_cast<std::uint64_t>(out[i]) != std::bit_cast<std::uint64_t>(std::sin(a[i]))) return false;
  }
  return true;
}

// Compiled for the instruction set (called only where the CPU has it).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
template void glibc_sin<Avx2Ops, 1>(const GlibcTable&, const double*, double*, unsigned*);
template void glibc_sin<Avx2Ops, 2>(const GlibcTable&, const double*, double*, unsigned*);
template void vector_sines<Avx2Ops>(const double*, double*, int);
template bool self_check<Avx2Ops>();
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
template void glibc_sin<Avx512Ops, 1>(const GlibcTable&, const double*, double*, unsigned*);
template void glibc_sin<Avx512Ops, 2>(const GlibcTable&, const double*, double*, unsigned*);
template void vector_sines<Avx512Ops>(const double*, double*, int);
template bool self_check<Avx512Ops>();
#pragma GCC pop_options

} // namespace

bool vector_sines_usable(SimdLevel level) {
  if (level == SimdLevel::Auto) level = best_simd_level();
  if (!simd_level_supported(level)) return false;
  switch (level) {
    case SimdLevel::Avx512: {
      static const bool ok = self_check<Avx512Ops>();
      return ok;
    }
    case SimdLevel::Avx2: {
      static const bool ok = self_check<Avx2Ops>();
      return ok;
    }
    default: return false;
  }
}

SinFn exact_sin_fn(SimdLevel level) {
  if (level == SimdLevel::Auto) level = best_simd_level();
  if (!vector_sines_usable(level)) return &scalar_sines;
  return level == SimdLevel::Avx512 ? &vector_sines<Avx512Ops> : &vector_sines<Avx2Ops>;
}

void exact_sines(const double* args, double* out, int n, SimdLevel level) {
  const SinFn fn = exact_sin_fn(level);
  constexpr int kBlock = kMaxWidth * 16;
  alignas(64) double a[kBlock], r[kBlock];
  for (int i = 0; i < n; i += kBlock) {
    const int k = std::min(n - i, kBlock);
    std::fill(a, a + kBlock, 1.0);
    std::copy(args + i, args + i + k, a);
    fn(a, r, k);
    std::copy(r, r + k, out + i);
  }
}

} // namespace soda
