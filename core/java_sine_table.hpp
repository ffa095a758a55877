// The numbers of the engine's sine (sine.hpp): the constants and the 64-row table
// of HotSpot's x86-64 Math.sin (Intel's LIBM algorithm, OpenJDK
// src/hotspot/cpu/x86/macroAssembler_x86_sin.cpp), as bit patterns.
//
// Shared by the scalar sine (sine.cpp) and the vector kernel
// (detail/java_sine_simd.hpp), so the two cannot drift apart. Plain C++ (no
// instruction-set headers): it builds on every target, WebAssembly included.
#pragma once

#include <bit>
#include <cstdint>

namespace soda::java_sine {

constexpr double from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

// The routine's main path covers 2^-252 <= |x| < 90112 (its bit test on the high
// word, |x| in [0x3030000000000000, 0x40F6000000000000)); below it returns x.
inline constexpr double kMainPathLow = from_bits(0x3030000000000000);  // 2^-252
inline constexpr double kMainPathEnd = from_bits(0x40F6000000000000);  // 90112

// Reduction x = N*pi/32 + r: N = (int)(x*32/pi +- 0.5), truncated; pi/32 in three
// parts, the first two short enough that N times them is exact.
inline constexpr double kThirtyTwoOverPi = from_bits(0x40245f306dc9c883);
inline constexpr double kPiOver32Part1 = from_bits(0x3fb921fb54400000);
inline constexpr double kPiOver32Part2 = from_bits(0x3d90b4611a600000);
inline constexpr double kPiOver32Part3 = from_bits(0x3b63198a2e037073);

// The polynomial, in two lanes evaluated side by side: lane "sin" for
// (sin(r) - r)/r^3 and lane "cos" for (cos(r) - 1)/r^2.
inline constexpr double kSc1Sin = from_bits(0xbfc5555555555555), kSc1Cos = from_bits(0xbfe0000000000000);
inline constexpr double kSc2Sin = from_bits(0x3f81111111111111), kSc2Cos = from_bits(0x3fa5555555555555);
inline constexpr double kSc3Sin = from_bits(0xbf2a01a01a01a01a), kSc3Cos = from_bits(0xbf56c16c16c16c17);
inline constexpr double kSc4Sin = from_bits(0x3ec71de3a556c734), kSc4Cos = from_bits(0x3efa01a01a01a01a);

/// One row per B = M*pi/32, M = N & 63: cos(B) - sigma, sin(B) as a high and a low
/// part, and sigma, the power of two nearest cos(B).
struct TableRow {
  double cos_minus_sigma, sin_high, sin_low, sigma;
};
constexpr int kTableRows = 64;
struct Table {
  alignas(64) TableRow row[kTableRows];
};

namespace detail {
// Rows 0..16 as HotSpot stores them; the others follow by symmetry, which is how
// HotSpot's table is laid out too: row 16+k is row 16-k reflected (B = pi - B':
// the same sine, cos - sigma and sigma negated), row 32+k is row k negated
// (B + pi). Zeros stay +0, as stored.
inline constexpr std::uint64_t kFirstRows[17][4] = {
    {0x0000000000000000, 0x0000000000000000, 0x0000000000000000, 0x3ff0000000000000},
    {0xbf73b92e176d6d31, 0x3fb917a6bc29b42c, 0xbc3e2718e0000000, 0x3ff0000000000000},
    {0xbf93ad06011469fb, 0x3fc8f8b83c69a60b, 0xbc626d19c0000000, 0x3ff0000000000000},
    {0xbfa60bea939d225a, 0x3fd294062ed59f06, 0xbc75d28da0000000, 0x3ff0000000000000},
    {0xbfb37ca1866b95cf, 0x3fd87de2a6aea963, 0xbc672cede0000000, 0x3ff0000000000000},
    {0xbfbe3a6873fa1279, 0x3fde2b5d3806f63b, 0x3c5e0d8920000000, 0x3ff0000000000000},
    {0xbfc592675bc57974, 0x3fe1c73b39ae68c8, 0x3c8b25dd20000000, 0x3ff0000000000000},
    {0xbfcd0dfe53aba2fd, 0x3fe44cf325091dd6, 0x3c68076a20000000, 0x3ff0000000000000},
    {0x3fca827999fcef32, 0x3fe6a09e667f3bcd, 0xbc8bdd3420000000, 0x3fe0000000000000},
    {0x3fc133cc94247758, 0x3fe8bc806b151741, 0xbc82c5e120000000, 0x3fe0000000000000},
    {0x3fac73b39ae68c87, 0x3fea9b66290ea1a3, 0x3c39f630e0000000, 0x3fe0000000000000},
    {0xbf9d4a2c7f909c4e, 0x3fec38b2f180bdb1, 0xbc76e0b180000000, 0x3fe0000000000000},
    {0xbfbe087565455a75, 0x3fed906bcf328d46, 0x3c7457e620000000, 0x3fe0000000000000},
    {0x3fa4a03176acf82d, 0x3fee9f4156c62dda, 0x3c8760b1e0000000, 0x3fd0000000000000},
    {0xbfac1d1f0e5967d5, 0x3fef6297cff75cb0, 0x3c75621720000000, 0x3fd0000000000000},
    {0xbf9ba1650f592f50, 0x3fefd88da3d12526, 0xbc887df640000000, 0x3fc0000000000000},
    {0x0000000000000000, 0x3ff0000000000000, 0x0000000000000000, 0x0000000000000000},
};

constexpr std::uint64_t negated(std::uint64_t b) { return b == 0 ? 0 : b ^ 0x8000000000000000ull; }

constexpr Table make_table() {
  Table t{};
  for (int m = 0; m < kTableRows; ++m) {
    const int k = m % 32;
    const bool second_half = m >= 32;
    std::uint64_t r[4];
    if (k <= 16) {
      for (int c = 0; c < 4; ++c) r[c] = kFirstRows[k][c];
    } else { // sin(B) = sin(pi - B), cos(B) = -cos(pi - B)
      const auto& s = kFirstRows[32 - k];
      r[0] = negated(s[0]), r[1] = s[1], r[2] = s[2], r[3] = negated(s[3]);
    }
    if (second_half) { // B + pi: everything negated
      for (auto& v : r) v = negated(v);
    }
    t.row[m] = {from_bits(r[0]), from_bits(r[1]), from_bits(r[2]), from_bits(r[3])};
  }
  return t;
}
} // namespace detail

/// HotSpot's table, rows M = 0..63 (built at compile time).
inline constexpr Table kTable = detail::make_table();

} // namespace soda::java_sine
