// SplitMix64's output function, the one 64-bit mixer of the project: every input
// bit moves every output bit. The sine jitter's hash (sine_jitter.hpp), the
// stability analysis's start vector, the GA's random numbers and the replica seeds
// (evolve/algorithms/rng.hpp, evolve/estimators/replica_estimator.cpp) all use it, so each is the same
// function of its inputs on every machine.
#pragma once

#include <cstdint>

namespace soda {

constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

} // namespace soda
