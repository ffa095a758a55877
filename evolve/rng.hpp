// Rng: the project's own random numbers, identical on every platform.
//
// std:: distributions differ between standard libraries, so runs would not
// reproduce elsewhere; this is SplitMix64 (Steele, Lea, Flood 2014) with our own
// uniform, integer and normal draws. Streams are derived from (seed, generation,
// individual, purpose) by hashing, so every child's randomness depends only on
// those numbers, never on thread scheduling or on how many draws others made.
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
  /// Standard normal (Box-Muller, one value per call).
  double normal();

  [[nodiscard]] std::uint64_t state() const { return state_; }

 private:
  std::uint64_t state_;
};

/// The SplitMix64 output function (core/mix64.hpp).
using soda::mix64;

} // namespace sodaevo
