// A double's bit pattern. Exactness is judged bit for bit: -0 and +0, and NaNs,
// are told apart, which == does not do; equal bits are equal values for every rule.
#pragma once

#include <bit>
#include <cstdint>

namespace soda {

inline std::uint64_t bits_of(double v) { return std::bit_cast<std::uint64_t>(v); }

} // namespace soda
