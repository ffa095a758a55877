#include "exact_sines.hpp"

#include <algorithm>
#include <bit>

#include "detail/java_sine_simd.hpp"
#include "detail/simd_ops.hpp"
#include "sine.hpp"

namespace soda {
namespace {

using simd::Avx2Ops;
using simd::Avx512Ops;
using simd::kMaxWidth;
using simd::Sse2Ops;

template <class O>
void vector_sines(const double* a, double* out, int n) {
  // Vector pass first, then the calls for lanes out of range (a call inside the
  // vector loop would spill every vector register around it).
  constexpr int kChunk = 256;
  unsigned rest[kChunk / O::W];
  for (int base = 0; base < n; base += kChunk) {
    const int end = std::min(n, base + kChunk);
    // Two vectors at a time (the arrays are padded to a multiple of 8 lanes; a
    // vector past n computes the padding and is not read).
    int i = base;
    for (; i + O::W < end; i += 2 * O::W) java_sine::java_sin<O, 2>(a + i, out + i, rest + (i - base) / O::W);
    if (i < end) java_sine::java_sin<O, 1>(a + i, out + i, rest + (i - base) / O::W);
    for (int i = base; i < end; i += O::W) {
      for (unsigned r = rest[(i - base) / O::W]; r != 0; r &= r - 1) {
        const int l = std::countr_zero(r);
        if (i + l < n) out[i + l] = sine(a[i + l]);
      }
    }
  }
}

// Compiled for the instruction set (called only where the CPU has it).
template void vector_sines<Sse2Ops>(const double*, double*, int);

#pragma GCC push_options
#pragma GCC target("avx2")
template void vector_sines<Avx2Ops>(const double*, double*, int);
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
template void vector_sines<Avx512Ops>(const double*, double*, int);
#pragma GCC pop_options

} // namespace

void scalar_sines(const double* a, double* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = sine(a[i]);
}

bool vector_sines_usable(SimdLevel level) {
  if (level == SimdLevel::Auto) level = best_simd_level();
  return simd_level_supported(level);
}

SinFn exact_sin_fn(SimdLevel level) {
  if (level == SimdLevel::Auto) level = best_simd_level();
  if (!vector_sines_usable(level)) return &scalar_sines;
  switch (level) {
  case SimdLevel::Avx512: return &vector_sines<Avx512Ops>;
  case SimdLevel::Avx2: return &vector_sines<Avx2Ops>;
  default: return &vector_sines<Sse2Ops>;
  }
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
