// Numbers from Python, checked at the boundary: a Python int, a numpy integer or
// anything with __index__ (a number for floats), in a range, else
// soda::InputError naming the argument, its range and what was given, never
// pybind11's "incompatible function arguments" or an overflow.
#pragma once

#include <cstdint>
#include <string>

#include <pybind11/pybind11.h>

namespace sodaevo::python {

namespace py = pybind11;

/// Most threads a call may ask for (the command line's --threads range).
inline constexpr long long kMaxThreads = 1024;

/// `value` as an integer in [low, high].
long long integer_in(const py::handle& value, const std::string& name, long long low, long long high);

/// `value` as a 64-bit seed, in [0, 2^64 - 1].
std::uint64_t seed_of(const py::handle& value, const std::string& name);

/// `value` as a finite number in [low, high].
double number_in(const py::handle& value, const std::string& name, double low, double high);

} // namespace sodaevo::python
