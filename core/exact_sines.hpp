// Exact sines: glibc's sin, bit for bit, several arguments at a time.
//
// The muscle rule (spec 5.1) takes the sine from std::sin, which is glibc's sin
// (sysdeps/ieee754/dbl-64/s_sin.c since glibc 2.28). That function is not
// correctly rounded, so no other sine gives its bits everywhere; but it is a
// fixed sequence of double operations on a 110-row table, with no slow path for
// |x| < 105414350. exact_sines.cpp repeats that sequence lane by lane in SIMD, as
// glibc's x86-64 build for CPUs with FMA (__sin_fma, chosen by glibc on every CPU
// with AVX2 and FMA) contracts it: the same fused and unfused operations on the
// same operands, so the same bits. Lanes outside that range, infinities and NaN
// call std::sin.
//
// A self-check against std::sin at first use, per instruction set, turns the
// vector path off if this C library's sin differs (another glibc version, or
// glibc's build without FMA); std::sin is then called for every argument. SSE2 has
// no fused multiply-add and always calls std::sin.
#pragma once

#include "simd_level.hpp"

namespace soda {

/// sin of n arguments, each equal bit for bit to std::sin's.
void exact_sines(const double* args, double* out, int n, SimdLevel level = SimdLevel::Auto);

/// Whether `level` computes sines in SIMD on this machine (supported, has FMA, and
/// the self-check against std::sin passed).
bool vector_sines_usable(SimdLevel level);

/// sin of a[0..n) into out[0..n); a and out padded to a multiple of 8 (kernels).
using SinFn = void (*)(const double* a, double* out, int n);
/// The vector sine of `level` where usable, else a loop over std::sin.
SinFn exact_sin_fn(SimdLevel level);

} // namespace soda
