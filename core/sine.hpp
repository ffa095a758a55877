// The engine's sine: Java's Math.sin, the same bits on every machine and build.
//
// The muscle rule (docs/physics.md) needs sin(2pi*(phi_m - phi_w)) for every
// muscle every frame, and walkers are chaotic: one sine that differs in its last
// bit sends a creature on another trajectory. The original SodaConstructor computes
// it with Java's Math.sin, which HotSpot on x86-64 (JDK 9 and later) computes with
// one fixed routine in the interpreter and in compiled code alike: Intel's LIBM
// algorithm (OpenJDK src/hotspot/cpu/x86/macroAssembler_x86_sin.cpp). soda::sine
// repeats that routine operation for operation: x = N*pi/32 + r with N =
// (int)(x*32/pi +- 0.5), a 64-row table at N & 63 (java_sine_table.hpp), a short
// polynomial and two compensated sums. It uses plain double additions and
// multiplications, no fused multiply-add (-ffp-contract=off holds everywhere), so
// it gives the same bits on every IEEE-754 machine, WebAssembly included, whatever
// the C library. The vector kernel (detail/java_sine_simd.hpp, through
// exact_sines.hpp) gives the same bits, several lanes at a time.
//
// Range: every double, each of the routine's paths repeated. The main path covers
// 2^-252 <= |x| < 90112 (muscle arguments lie within (-2pi, 2pi)); below it the
// routine returns x; above it, it first reduces x by pi/4 with a long binary
// expansion of 2/pi (java_sine_large.hpp) and ends in the main path; for
// infinities it returns the NaN 0xfff8000000000000 and a NaN quieted, as x86 does.
#pragma once

namespace soda {

/// Java's Math.sin(x) (HotSpot, x86-64, JDK 9 and later), bit for bit, for every x.
double sine(double x);

} // namespace soda
