#include "sine_jitter.hpp"

#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace soda {
namespace {

/// splitmix64's finaliser: every input bit reaches every output bit.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// floor(p * 2^53) for p in [0, 1] (exact: a power-of-two scaling).
std::uint64_t threshold(double probability) {
  if (!(probability > 0.0)) return 0;
  if (probability >= 1.0) return std::uint64_t{1} << 53;
  return static_cast<std::uint64_t>(probability * 0x1p53);
}

} // namespace

int jitter_steps(double argument, const SineJitter& jitter) {
  if (jitter.seed == 0) return 0;
  const std::uint64_t h = mix64(std::bit_cast<std::uint64_t>(argument) ^ mix64(jitter.seed));
  if ((h >> 11) >= threshold(jitter.probability)) return 0;
  return (h & 1) != 0 ? 1 : -1;
}

double jittered(double sine_value, double argument, const SineJitter& jitter) {
  const int steps = jitter_steps(argument, jitter);
  if (steps == 0) return sine_value;
  return std::nextafter(sine_value, steps > 0 ? HUGE_VAL : -HUGE_VAL);
}

void require_valid_jitter(const SineJitter& jitter, const char* what) {
  if (!(jitter.probability >= 0.0 && jitter.probability <= 1.0)) {
    throw std::invalid_argument(std::string(what) + ": sine jitter probability must be in [0, 1], got " +
                                std::to_string(jitter.probability));
  }
}

void require_valid_jitter_of(const SineJitter& jitter, const char* who, int index) {
  if (jitter.probability >= 0.0 && jitter.probability <= 1.0) return; // no message built on the hot path
  require_valid_jitter(jitter, (std::string(who) + ": state " + std::to_string(index)).c_str());
}


} // namespace soda
