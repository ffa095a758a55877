#include "sine_jitter.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace soda {
namespace {

/// floor(p * 2^53) for p in [0, 1] (exact: a power-of-two scaling).
std::uint64_t jitter_threshold(double probability) {
  if (!(probability > 0.0)) return 0;
  if (probability >= 1.0) return std::uint64_t{1} << 53;
  return static_cast<std::uint64_t>(probability * 0x1p53);
}

} // namespace

PreparedJitter::PreparedJitter(const SineJitter& jitter)
    : seed_mix(mix64(jitter.seed)), threshold(jitter.seed == 0 ? 0 : jitter_threshold(jitter.probability)) {}

int jitter_steps(double argument, const SineJitter& jitter) { return PreparedJitter(jitter).steps(argument); }

double jittered(double sine_value, double argument, const SineJitter& jitter) {
  return PreparedJitter(jitter).apply(sine_value, argument);
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
