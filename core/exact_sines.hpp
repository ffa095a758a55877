// Exact sines: the engine's sine (sine.hpp), several arguments at a time.
//
// soda::sine is glibc's x86-64 FMA sin: a fixed sequence of double operations on
// a 110-row table, some of them fused. detail/glibc_sine.hpp repeats that sequence lane
// by lane in SIMD (AVX2 with FMA, AVX-512): the same fused and unfused operations
// on the same operands, so the same bits as sine. Lanes outside sine's range
// (|x| >= 105414336, infinities, NaN) take sine's result. SSE2 has no fused
// multiply-add: there, and on CPUs without AVX2, the sines come from sine one by
// one. Every level gives the same bits (tests/test_sine.cpp).
#pragma once

#include "simd_level.hpp"

namespace soda {

/// sine of n arguments, each equal bit for bit to soda::sine's.
void exact_sines(const double* args, double* out, int n, SimdLevel level = SimdLevel::Auto);

/// Whether `level` computes sines in SIMD on this machine (AVX2 with FMA or
/// AVX-512, and supported by the CPU).
bool vector_sines_usable(SimdLevel level);

/// sine of a[0..n) into out[0..n); a and out padded to a multiple of 8 (kernels).
using SinFn = void (*)(const double* a, double* out, int n);
/// The vector sine of `level` where usable, else a loop over soda::sine.
SinFn exact_sin_fn(SimdLevel level);

} // namespace soda
