// Sine jitter: a replica's "other libm", so that an ensemble of runs shows how
// far a creature's result depends on the last bit of its sines.
//
// Why: SodaConstructor's own engine (the JVM's Math.sin) and this one agree bit
// for bit until the first muscle sine where the two libraries differ by one unit
// in the last place (0.19 % of arguments); a walker is chaotic, so from there on
// the original's run is another draw from the creature's distribution of
// distances. A replica with a nonzero seed moves the sine by +-1 ulp for a share
// `probability` of arguments, which models exactly that. The choice is a pure
// function of the argument's bits and the seed (a fixed hash below), so a replica
// gives the same trajectory on every machine, thread count and rank. Seed 0 is
// the exact engine.
#pragma once

#include <cstdint>

namespace soda {

/// A replica's other libm: sine results moved by +-1 ulp for a share `probability` of
/// arguments, chosen by a hash of the argument's bits and `seed`. seed 0 = exact (no jitter).
struct SineJitter {
  std::uint64_t seed = 0;
  double probability = 0.002; // [0, 1]
  bool operator==(const SineJitter&) const = default;
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
