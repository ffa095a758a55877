// Rng: the project's own random numbers, identical on every platform.
//
// std:: distributions differ between standard libraries, so runs would not
// reproduce elsewhere; this is SplitMix64 (Steele, Lea, Flood 2014) with our own
// uniform, integer and normal draws. Streams are derived from (seed, generation,
// individual, purpose) by hashing, so every child's randomness depends only on
// those numbers, never on thread scheduling or on how many draws others made.
//
// No C library function with a rounding of its own: the C library's log, cos and
// hypot differ between libraries and, on x86-64 glibc, between CPUs (FMA or not),
// so a mutation drawn with them, and the whole run after it, would differ from
// machine to machine. normal() uses portable_log (below) and the engine's own
// sine (core/sine.hpp); everything else is +, -, *, / and sqrt, which IEEE 754
// rounds the same everywhere.
#pragma once

#include <cstdint>

#include "core/mix64.hpp"

namespace sodaevo {

class Rng {
 public:
  explicit Rng(std::uint64_t state) : state_(state) {}

  /// A stream for (seed, a, b, c): e.g. (seed, generation, individual, purpose).
  static Rng stream(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0, std::uint64_t c = 0);

  std::uint64_t next_u64();
  /// Uniform in [0, 1), 53 random bits.
  double uniform();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0, without modulo bias.
  std::uint64_t below(std::uint64_t n);
  /// Uniform int in [lo, hi] (inclusive).
  int between(int lo, int hi);
  /// True with probability p.
  bool chance(double p) { return uniform() < p; }
  /// Standard normal (Box-Muller, one value per call): sqrt(-2 log u1) sin(2 pi u2).
  double normal();

  [[nodiscard]] std::uint64_t state() const { return state_; }

 private:
  std::uint64_t state_;
};

/// The natural log of a positive finite x, within 2 units in the last place, the
/// same bits on every machine: x = m 2^e with m in [sqrt(1/2), sqrt(2)), and
/// log m = 2 atanh(s), s = (m - 1) / (m + 1), by its series. NaN for x <= 0, NaN
/// or infinity.
double portable_log(double x);

/// The SplitMix64 output function (core/mix64.hpp).
using soda::mix64;

} // namespace sodaevo
