// Java's Math.sin for |x| >= 90112: HotSpot's reduction of a large argument
// (sine.hpp says what and why; sine.cpp runs the rest of the routine).
//
// The routine's main path reduces x by pi/32 in three parts, exact only while N =
// x*32/pi stays small. Above 90112 it first reduces x modulo pi/4 with a long
// binary expansion of 2/pi (Payne-Hanek: the 53-bit significand times 96 bits of
// 2/pi chosen by the exponent, in 32-bit pieces), then runs the main path on the
// remainder with its low part and the quadrant. The integer steps are repeated
// here register for register, the 32-bit ones with their 32-bit wrap and shift
// counts, so the remainder has the routine's bits.
#pragma once

namespace soda::java_sine {

/// x reduced by the routine's large-argument path: x = k*pi/4 + (high + low)
/// (approximately), and `rows`, the table rows the quadrant adds to N.
struct LargeReduction {
  double high = 0.0;
  double low = 0.0;
  unsigned rows = 0; ///< added to N before N & 63 (8 rows per quarter turn)
};

/// For finite |x| >= 90112.
LargeReduction reduce_large(double x);

} // namespace soda::java_sine
