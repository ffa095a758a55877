// Sine jitter: a replica's "other libm", so that an ensemble of runs shows how
// far a creature's result depends on the last bit of its sines.
//
// Why: this engine computes the original's sine (Java's Math.sin as an x86-64 JDK
// 9+ does, sine.hpp), but a creature also meets other machines' sines: a JVM on
// aarch64 or JDK 8, another language's sin (glibc's differs from Java's by one unit
// in the last place for about 0.2 % of muscle arguments). A walker is chaotic, so
// from the first sine that differs its run is another draw from the creature's
// distribution of distances. A replica with a nonzero seed moves the sine by +-1
// ulp for a share `probability` of arguments, which models exactly that. The choice is a pure
// function of the argument's bits and the seed (a fixed hash below), so a replica
// gives the same trajectory on every machine, thread count and rank. Seed 0 is
// the exact engine.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "mix64.hpp"

namespace soda {

/// A replica's other libm: sine results moved by +-1 ulp for a share `probability` of
/// arguments, chosen by a hash of the argument's bits and `seed`. seed 0 = exact (no jitter).
struct SineJitter {
  std::uint64_t seed = 0;
  double probability = 0.002; // [0, 1]
  bool operator==(const SineJitter&) const = default;
};

/// A SineJitter made ready for many arguments: the seed's mix and the threshold
/// formed once, so that the steppers' loops hash each argument with one mix64
/// (the lockstep lanes do it for 8 lanes at once from these two numbers).
struct PreparedJitter {
  std::uint64_t seed_mix = 0;  ///< mix64(seed)
  std::uint64_t threshold = 0; ///< floor(probability * 2^53); 0 for seed 0: nothing moves
  PreparedJitter() = default;
  explicit PreparedJitter(const SineJitter& jitter);
  /// jitter_steps(argument, the jitter this was made from).
  [[nodiscard]] int steps(double argument) const {
    if (threshold == 0) return 0;
    std::uint64_t bits = 0;
    std::memcpy(&bits, &argument, sizeof bits);
    const std::uint64_t h = mix64(bits ^ seed_mix);
    if ((h >> 11) >= threshold) return 0;
    return (h & 1) != 0 ? 1 : -1;
  }
  /// jittered(sine_value, argument, the jitter this was made from).
  [[nodiscard]] double apply(double sine_value, double argument) const {
    const int s = steps(argument);
    return s == 0 ? sine_value : std::nextafter(sine_value, s > 0 ? HUGE_VAL : -HUGE_VAL);
  }
};

/// -1, 0 or +1: the ulp steps for this argument (0 whenever seed == 0).
/// h = mix64(bits(argument) ^ mix64(seed)), mix64 the splitmix64 finaliser; a hit
/// iff (h >> 11) < floor(probability * 2^53); then +1 if h is odd, else -1.
int jitter_steps(double argument, const SineJitter& jitter);

/// sine moved by jitter_steps ulps toward +inf (+1) or -inf (-1) (std::nextafter).
double jittered(double sine_value, double argument, const SineJitter& jitter);

/// Throws std::invalid_argument naming `what` unless probability is in [0, 1].
void require_valid_jitter(const SineJitter& jitter, const char* what);

/// require_valid_jitter for state `index` of a batch stepped by `who` (names both).
void require_valid_jitter_of(const SineJitter& jitter, const char* who, int index);

} // namespace soda
