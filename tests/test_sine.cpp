// The engine's sine (core/sine.hpp) against this machine's glibc sin, and every
// other path to it (the portable build, the vector kernels) against it.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__GLIBC__)
#include <gnu/libc-version.h>
#endif

#include "core/constants.hpp"
#include "core/exact_sines.hpp"
#include "core/simd_level.hpp"
#include "core/sine.hpp"

namespace {

// The ASan build runs every test too; it is several times slower.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kScale = 16;
#else
constexpr int kScale = 1;
#endif

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

/// Whether std::sin here is glibc's x86-64 FMA build, the definition of
/// soda::sine: glibc 2.28 or later (the sin of s_sin.c as it is since), on an
/// x86-64 CPU with AVX2 and FMA (glibc's condition for picking __sin_fma).
bool std_sin_is_glibc_fma() {
#if defined(__GLIBC__) && defined(__x86_64__)
  if (__GLIBC__ < 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ < 28)) return false;
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

struct Random {
  std::uint64_t state;
  std::uint64_t next() { // splitmix64
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1p-53; } // [0, 1)
};

/// Arguments from every branch of glibc's sin below 105414336, its ends, and the
/// cases where the reduction cancels most (near multiples of pi/2).
std::vector<double> arguments() {
  Random random{26};
  std::vector<double> args;
  // Muscle arguments 2pi*(phi_m - phi_w): uniform phases, and quantised muscle
  // phases k/255 (as saved files have them) against a running wave.
  for (int i = 0; i < 6'000'000 / kScale; ++i) args.push_back(soda::kTwoPi * (random.uniform() - random.uniform()));
  for (int k = 0; k < 255; ++k) {
    double wave = random.uniform();
    for (int f = 0; f < 2000 / kScale; ++f) {
      args.push_back(soda::kTwoPi * (static_cast<double>(static_cast<float>(k / 255.0)) - wave));
      wave = wave + 2.5 / 255.0;
      if (wave >= 1.0) wave -= 1.0;
    }
  }
  // Every magnitude from 2^-30 to the end of the range, both signs (log-uniform).
  for (int i = 0; i < 2'000'000 / kScale; ++i) {
    const double magnitude = std::exp2(-30.0 + 56.65 * random.uniform());
    args.push_back(random.next() & 1 ? magnitude : -magnitude);
  }
  // Tiny, subnormal and signed zeros.
  for (double v : {0.0, 0x1p-1074, 0x1p-1022, 0x1.fffffffffffffp-1023, 1e-300, 1e-20, 0x1p-27}) {
    args.push_back(v);
    args.push_back(-v);
  }
  // The ends of the branches (2^-26, the Taylor polynomial's 0.126, 0.85546875,
  // 0x1.368fdp+1, 105414336), glibc's table points i/128 and the midpoints between
  // them (ties in the rounding to the nearest point), the reduction's multiples of
  // pi/4, and multiples of pi/2 up to 2^26 (where x - n pi/2 cancels most):
  // neighbours on each side, both signs.
  std::vector<double> edges = {0x1p-26, 0.126, 0x1.b6p-1, 0x1.368fdp+1, soda::sine_range_end()};
  for (int i = 1; i <= 110; ++i) {
    edges.push_back(i / 128.0);
    edges.push_back((i - 0.5) / 128.0);
  }
  for (int k = 1; k <= 64; ++k) edges.push_back(k * 0.7853981633974483);
  for (double k = 1.0; k < 6.7e7; k = std::ceil(k * 1.01)) edges.push_back(k * 1.5707963267948966);
  for (double edge : edges) {
    double up = edge, down = edge;
    for (int k = 0; k < 200 / kScale; ++k) {
      for (double v : {up, down}) {
        if (std::fabs(v) < 105414336.0) {
          args.push_back(v);
          args.push_back(-v);
        }
      }
      up = std::nextafter(up, 1e9);
      down = std::nextafter(down, 0.0);
    }
  }
  return args;
}

const std::vector<double>& shared_arguments() {
  static const std::vector<double> args = arguments();
  return args;
}

} // namespace

TEST_CASE("soda::sine equals glibc's FMA sin bit for bit", "[sine]") {
  if (!std_sin_is_glibc_fma()) {
    WARN("skipped: std::sin here is not glibc's x86-64 FMA build (glibc >= 2.28 on a CPU with AVX2 and FMA)");
    return;
  }
#if defined(__GLIBC__)
  INFO("glibc " << gnu_get_libc_version());
#endif
  const std::vector<double>& args = shared_arguments();
  std::size_t bad = 0;
  double first_bad = 0.0;
  for (double x : args) {
    if (bits(soda::sine(x)) != bits(std::sin(x))) {
      if (bad++ == 0) first_bad = x;
    }
  }
  INFO(args.size() << " arguments; first that differs: " << first_bad);
  CHECK(bad == 0);
}

TEST_CASE("the portable sine and the vector kernels give soda::sine's bits", "[sine]") {
  const std::vector<double>& args = shared_arguments();
  // The portable build's path (std::fma as a library call), on every 4th argument
  // (it is slow where the CPU has the instruction).
  std::size_t bad = 0;
  for (std::size_t i = 0; i < args.size(); i += 4) {
    bad += bits(soda::detail::sine_portable(args[i])) == bits(soda::sine(args[i])) ? 0 : 1;
  }
  CHECK(bad == 0);

  std::vector<double> with_ends = args;
  for (double v : {105414336.0, -105414336.0, 1e9, -1e300, HUGE_VAL, -HUGE_VAL,
                   std::numeric_limits<double>::quiet_NaN()}) {
    with_ends.push_back(v);
  }
  std::vector<double> out(with_ends.size());
  for (soda::SimdLevel level : {soda::SimdLevel::Sse2, soda::SimdLevel::Avx2, soda::SimdLevel::Avx512}) {
    if (!soda::simd_level_supported(level)) {
      WARN("vector sines at " << soda::simd_level_name(level) << " skipped: not supported by this CPU");
      continue;
    }
    soda::exact_sines(with_ends.data(), out.data(), static_cast<int>(with_ends.size()), level);
    bad = 0;
    for (std::size_t i = 0; i < with_ends.size(); ++i) bad += bits(out[i]) == bits(soda::sine(with_ends[i])) ? 0 : 1;
    INFO(soda::simd_level_name(level));
    CHECK(bad == 0);
  }
}

TEST_CASE("soda::sine outside its range is NaN, never the C library's", "[sine]") {
  const double end = soda::sine_range_end();
  CHECK(std::nextafter(end, 1e300) == 105414336.0);
  CHECK(std::isfinite(soda::sine(end)));
  CHECK(std::isfinite(soda::sine(-end)));
  for (double v : {105414336.0, -105414336.0, 1e9, 1e300, -1e300, HUGE_VAL, -HUGE_VAL,
                   std::numeric_limits<double>::quiet_NaN()}) {
    INFO(v);
    CHECK(std::isnan(soda::sine(v)));
    CHECK(std::isnan(soda::detail::sine_portable(v)));
  }
}
