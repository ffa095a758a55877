#include "simd_level.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

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

namespace {

SimdLevel cpu_best() {
  if (simd_level_supported(SimdLevel::Avx512)) return SimdLevel::Avx512;
  if (simd_level_supported(SimdLevel::Avx2)) return SimdLevel::Avx2;
  return SimdLevel::Sse2;
}

SimdLevel capped(SimdLevel level) {
  if (level == SimdLevel::Auto || !simd_level_supported(level)) return cpu_best();
  return level;
}

SimdLevel from_environment() {
  SimdLevel level = SimdLevel::Auto;
  const char* name = std::getenv("SODAEVO_SIMD");
  if (name != nullptr && *name != '\0' && !parse_simd_level(name, level)) {
    std::fprintf(stderr, "sodaevo: SODAEVO_SIMD=%s is not a SIMD level (auto, sse2, avx2, avx512); using the CPU's best\n", name);
  }
  return capped(level);
}

std::atomic<SimdLevel>& forced() {
  static std::atomic<SimdLevel> level{from_environment()};
  return level;
}

} // namespace

SimdLevel best_simd_level() { return forced().load(std::memory_order_relaxed); }

void force_simd_level(SimdLevel level) { forced().store(capped(level), std::memory_order_relaxed); }

bool parse_simd_level(const char* name, SimdLevel& level) {
  for (SimdLevel l : {SimdLevel::Auto, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512}) {
    if (std::strcmp(name, simd_level_name(l)) == 0) {
      level = l;
      return true;
    }
  }
  return false;
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
