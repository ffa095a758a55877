#include "bench/host_probes.hpp"

#include <unistd.h>

#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

#include "core/detail/simd_ops.hpp"

namespace sodaevo::bench {

namespace {

// GCC 12 takes the undefined pass-through operand of _mm512_sqrt_pd for an
// uninitialised variable once it is inlined here: a false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class O>
double divider_passes(std::size_t i) {
  using V = typename O::V;
  V v[8];
  for (int k = 0; k < 8; ++k) v[k] = O::set1(2.5 + static_cast<double>((i + static_cast<std::size_t>(k)) % 7));
  const V shift = O::set1(1.5), divisor = O::set1(1.0000001);
  for (int pass = 0; pass < 40000; ++pass) {
    for (int k = 0; k < 4; ++k) v[k] = O::sqrt(O::add(v[k], shift)); // stays near 1.8
    for (int k = 4; k < 8; ++k) v[k] = O::div(v[k], divisor);
  }
  double lanes[soda::simd::kMaxWidth] = {};
  double sum = 0.0;
  for (const V& x : v) {
    O::storeu(lanes, x);
    sum += lanes[0];
  }
  return sum;
}
// Compiled for each instruction set (called only where the CPU has it), as
// core/exact_sines.cpp does.
#pragma GCC push_options
#pragma GCC target("avx2")
template double divider_passes<soda::simd::Avx2Ops>(std::size_t);
double divider_avx2(std::size_t i) { return divider_passes<soda::simd::Avx2Ops>(i); }
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx512f")
template double divider_passes<soda::simd::Avx512Ops>(std::size_t);
double divider_avx512(std::size_t i) { return divider_passes<soda::simd::Avx512Ops>(i); }
#pragma GCC pop_options
#pragma GCC diagnostic pop

} // namespace

double arithmetic_item(std::size_t i) {
  double acc[16];
  for (int k = 0; k < 16; ++k) acc[k] = 1.0 + static_cast<double>((i + k) % 7);
  for (int pass = 0; pass < 400000; ++pass) {
    for (double& a : acc) a = a * 0.9999999 + 1e-7;
  }
  double sum = 0.0;
  for (double a : acc) sum += a;
  return sum;
}

double divider_item(std::size_t i, soda::SimdLevel level) {
  switch (level) {
    case soda::SimdLevel::Avx512: return divider_avx512(i);
    case soda::SimdLevel::Avx2: return divider_avx2(i);
    default: return divider_passes<soda::simd::Sse2Ops>(i);
  }
}

std::vector<int> cores_to_pin(int wanted) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return {};
  std::vector<int> cores;
  for (int c = 0; c < CPU_SETSIZE && static_cast<int>(cores.size()) < wanted; ++c) {
    if (CPU_ISSET(c, &set)) cores.push_back(c);
  }
  if (static_cast<int>(cores.size()) < wanted) return {};
  return cores;
}

CoreHold::CoreHold(int core) {
  if (core < 0 || sched_getaffinity(0, sizeof saved_, &saved_) != 0) return;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(core, &one);
  held_ = sched_setaffinity(0, sizeof one, &one) == 0;
}

CoreHold::~CoreHold() noexcept(false) {
  // Failing to let go would leave every later thread on one core, and the
  // all-thread figures wrong without a word.
  if (held_ && sched_setaffinity(0, sizeof saved_, &saved_) != 0 && std::uncaught_exceptions() == 0) {
    throw std::runtime_error("bench speed: could not release the 1-thread run's hold on its core");
  }
}

double steal_ms() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  long long value[8];
  if (!(stat >> cpu) || cpu != "cpu") return -1.0;
  for (long long& v : value) {
    if (!(stat >> v)) return -1.0;
  }
  const long ticks_per_second = sysconf(_SC_CLK_TCK);
  return ticks_per_second > 0 ? static_cast<double>(value[7]) * 1000.0 / static_cast<double>(ticks_per_second) : -1.0;
}

} // namespace sodaevo::bench
