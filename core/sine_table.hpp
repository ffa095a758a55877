// The numbers of the engine's sine (sine.hpp): glibc's constants and its 110-row
// table of sin and cos at i/128.
//
// Shared by the scalar sine (sine.cpp) and the vector kernel (detail/glibc_sine.hpp), so
// the two cannot drift apart. Plain C++ (no instruction-set headers): it builds on
// every target, WebAssembly included.
#pragma once

#include <bit>
#include <cstdint>

namespace soda::glibc_sine {

constexpr double from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

// The branches of glibc's sin by |x| (sysdeps/ieee754/dbl-64/s_sin.c):
//   |x| < 2^-26                  x
//   |x| < 0.85546875             do_sin(x, 0)
//   |x| < 2.426265 (0x400368fd)  copysign(do_cos(pi/2 - |x|, pi/2 low), x)
//   |x| < 105414336 (0x419921fb) x reduced by pi/2 to (a, da) and quadrant n:
//                                do_sin(a, da) or do_cos(a, da) by n's parity,
//                                negated when n & 2
// and do_sin switches to a Taylor polynomial for |a| < 0.126.
inline constexpr double kTinyBound = 0x1p-26;
inline constexpr double kSinBound = from_bits(0x3feb600000000000);    // 0.85546875
inline constexpr double kCosBound = from_bits(0x400368fd00000000);    // 2.426265...
inline constexpr double kReduceBound = from_bits(0x419921fb00000000); // 105414336 = 0x1.921fbp+26
inline constexpr double kTaylorBound = 0.126;

// glibc's constants (s_sin.c, usncs.h), by their bits.
inline constexpr double kBig = from_bits(0x42c8000000000000); // 1.5 * 2^45: adding it rounds to 1/128
inline constexpr double kToInt = from_bits(0x4338000000000000);
inline constexpr double kHalfPiInverse = from_bits(0x3fe45f306dc9c883);
inline constexpr double kHalfPi1 = from_bits(0x3ff921fb58000000);
inline constexpr double kHalfPi2 = from_bits(0xbe4dde973c000000);
inline constexpr double kHalfPi3 = from_bits(0xbc8cb3b398000000);
inline constexpr double kHalfPi4 = from_bits(0xbacd747f23e32ed7);
inline constexpr double kHalfPiHigh = from_bits(0x3ff921fb54442d18);
inline constexpr double kHalfPiLow = from_bits(0x3c91a62633145c07);
inline constexpr double kSn3 = from_bits(0xbfc5555555555515);
inline constexpr double kSn5 = from_bits(0x3f811110e829872f);
inline constexpr double kCs2 = 0.5;
inline constexpr double kCs4 = from_bits(0xbfa5555555555535);
inline constexpr double kCs6 = from_bits(0x3f56c16bedd9e239);
inline constexpr double kS1 = from_bits(0xbfc5555555555555);
inline constexpr double kS2 = from_bits(0x3f81111111110ece);
inline constexpr double kS3 = from_bits(0xbf2a01a019db08b8);
inline constexpr double kS4 = from_bits(0x3ec71de27b9a7ed9);
inline constexpr double kS5 = from_bits(0xbe5addffc2fcdf59);

// glibc's table: sin(i/128) and cos(i/128), i = 0..109, each as a high double and
// a low double (row: sin high, sin low, cos high, cos low); built in sine_table.cpp.
constexpr int kTableRows = 110;
struct GlibcTable {
  alignas(64) double row[kTableRows][4];
};

/// The table, built at first use.
const GlibcTable& glibc_table();

} // namespace soda::glibc_sine
