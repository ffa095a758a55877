#include "exact_sines.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "glibc_sine.hpp"
#include "simd_ops.hpp"

namespace soda {
namespace {

using simd::Avx2Ops;
using simd::Avx512Ops;
using simd::kMaxWidth;
using namespace glibc_sine;

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
template void vector_sines<Avx2Ops>(const double*, double*, int);
template bool self_check<Avx2Ops>();
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
template void vector_sines<Avx512Ops>(const double*, double*, int);
template bool self_check<Avx512Ops>();
#pragma GCC pop_options

} // namespace

const glibc_sine::GlibcTable& glibc_sine::glibc_table() {
  static const GlibcTable table = build_glibc_table();
  return table;
}

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
