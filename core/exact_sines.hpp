// Exact sines: the engine's sine (sine.hpp), several arguments at a time.
//
// soda::sine is HotSpot's x86-64 Math.sin: a fixed sequence of plain double
// operations on a 64-row table. detail/java_sine_simd.hpp repeats that sequence lane
// by lane in SIMD (SSE2, AVX2, AVX-512): the same operations on the same operands,
// so the same bits as sine. Lanes above the main path (|x| >= 90112: the large-
// argument reduction; infinities, NaN) take sine's result. Every level gives the same bits (tests/test_sine.cpp).
#pragma once

#include "simd_level.hpp"

namespace soda {

/// sine of n arguments, each equal bit for bit to soda::sine's.
void exact_sines(const double* args, double* out, int n, SimdLevel level = SimdLevel::Auto);

/// Whether `level` computes sines in SIMD on this machine (any SIMD level the
/// CPU supports; Auto: the best).
bool vector_sines_usable(SimdLevel level);

/// sine of a[0..n) into out[0..n); a and out padded to a multiple of 8 (kernels).
using SinFn = void (*)(const double* a, double* out, int n);
/// The vector sine of `level` where usable, else a loop over soda::sine.
SinFn exact_sin_fn(SimdLevel level);

/// A loop over soda::sine: the scalar path, for the tests and the stepper option
/// that turns vector sines off.
void scalar_sines(const double* a, double* out, int n);

} // namespace soda
