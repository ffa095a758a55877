#include "rng.hpp"

#include <cmath>

namespace sodaevo {

namespace {
constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;
}


Rng Rng::stream(std::uint64_t seed, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  std::uint64_t h = mix64(seed + kGolden);
  h = mix64(h ^ (a + 0x632BE59BD9B4E019ull));
  h = mix64(h ^ (b + 0x8CB92BA72F3D8DD7ull));
  h = mix64(h ^ (c + 0xA0761D6478BD642Full));
  return Rng(h);
}

std::uint64_t Rng::next_u64() { return mix64(state_ += kGolden); }

double Rng::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
  // Rejection of the short top range keeps every value equally likely.
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  for (;;) {
    const std::uint64_t r = next_u64();
    if (r < limit) return r % n;
  }
}

int Rng::between(int lo, int hi) {
  return lo + static_cast<int>(below(static_cast<std::uint64_t>(static_cast<long long>(hi) - lo + 1)));
}

double Rng::normal() {
  // 1 - uniform() is in (0, 1], so the log is finite.
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

} // namespace sodaevo
