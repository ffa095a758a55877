// glibc's sine table (sine_table.hpp), computed here rather than copied.
#include "sine_table.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace soda::glibc_sine {
namespace {

// ---------------------------------------------------------------------------
// glibc's table: sin(i/128) and cos(i/128), i = 0..109, each as a high double and
// a low double (row: sin high, sin low, cos high, cos low).
//
// The high parts are the nearest doubles; the low parts are the nearest doubles to
// the rest, except in 18 places where glibc's table (__sincostab) is 1, 2 or 39
// units of the last place off that (compared with a dump of glibc 2.36's
// __sincostab). We compute the nearest values from a 256-bit fixed-point Taylor
// series and apply those 18 offsets; the tests compare the whole sine with
// std::sin (tests/test_sine.cpp).
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

} // namespace

const GlibcTable& glibc_table() {
  static const GlibcTable table = build_glibc_table();
  return table;
}

} // namespace soda::glibc_sine
