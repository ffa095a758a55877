// The engine's sine: one function, the same bits on every machine and build.
//
// The muscle rule (docs/physics.md) needs sin(2pi*(phi_m - phi_w)) for every
// muscle every frame, and walkers are chaotic: one sine that differs in its last
// bit sends a creature on another trajectory. The C library's sin differs between
// machines (glibc on x86-64 picks an FMA or a non-FMA variant by CPU, musl and
// Emscripten have their own), so the engine never calls it. soda::sine is
// instead the bits of glibc's x86-64 FMA build (__sin_fma, glibc 2.28 and later),
// the function the reference traces were compared with: glibc's fixed sequence of
// double operations on a 110-row table (sine_table.hpp), with std::fma exactly
// where that build fuses. std::fma is correctly rounded on every platform, so the
// result does not depend on the CPU, the compiler's contraction (-ffp-contract=off
// holds everywhere) or the C library. The vector kernel (detail/glibc_sine.hpp, through
// exact_sines.hpp) gives the same bits, several lanes at a time.
//
// Range. Every branch of glibc's sin for |x| < 105414336 is repeated here; muscle
// arguments lie within (-2pi, 2pi), far inside. Beyond that glibc reduces x with
// a multi-precision 2/pi (its __branred), which is not repeated: sine returns NaN
// for finite |x| >= 105414336, as for infinities and NaN. A NaN muscle target
// makes the state non-finite, which every stepper's blow-up check reports; it is
// never a silently different number.
#pragma once

namespace soda {

/// sin(x): glibc's x86-64 FMA sin, bit for bit, for |x| < 105414336; NaN for
/// larger |x|, infinities and NaN.
double sine(double x);

/// The largest |x| sine computes: the next double down from 0x1.921fbp+26 =
/// 105414336 (glibc's comments round that bound to 105414350).
double sine_range_end();

namespace detail {
/// sine compiled for the baseline instruction set (std::fma as a library call
/// where the CPU has no fused multiply-add): the path of builds for other CPUs,
/// WebAssembly included. For the tests, which compare it with sine.
double sine_portable(double x);
} // namespace detail

} // namespace soda
