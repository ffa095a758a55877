#include "simd_level.hpp"

namespace soda {

bool simd_level_supported(SimdLevel level) {
  switch (level) {
    case SimdLevel::Auto:
    case SimdLevel::Sse2: return true;
#if defined(__x86_64__) || defined(__i386__)
    case SimdLevel::Avx2: return __builtin_cpu_supports("avx2");
    case SimdLevel::Avx512: return __builtin_cpu_supports("avx512f");
#else // WebAssembly: 128-bit vectors only (core/detail/simd_ops.hpp)
    case SimdLevel::Avx2:
    case SimdLevel::Avx512: return false;
#endif
  }
  return false;
}

SimdLevel best_simd_level() {
  if (simd_level_supported(SimdLevel::Avx512)) return SimdLevel::Avx512;
  if (simd_level_supported(SimdLevel::Avx2)) return SimdLevel::Avx2;
  return SimdLevel::Sse2;
}

const char* simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::Auto: return "auto";
    case SimdLevel::Sse2: return "sse2";
    case SimdLevel::Avx2: return "avx2";
    case SimdLevel::Avx512: return "avx512";
  }
  return "?";
}

} // namespace soda
