#include "python/arguments.hpp"

#include <cmath>
#include <limits>

#include "core/input_error.hpp"

namespace sodaevo::python {

namespace {

[[noreturn]] void refuse(const std::string& name, const std::string& expected, const py::handle& value) {
  throw soda::InputError(name + ": expected " + expected + ", got " + py::repr(value).cast<std::string>());
}

/// value.__index__() (ints and numpy integers, not floats or bools), or nullptr.
py::object as_index(const py::handle& value) {
  if (PyBool_Check(value.ptr()) || PyFloat_Check(value.ptr())) return {};
  PyObject* index = PyNumber_Index(value.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    return {};
  }
  return py::reinterpret_steal<py::object>(index);
}

} // namespace

long long integer_in(const py::handle& value, const std::string& name, long long low, long long high) {
  const std::string range = "an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
  const py::object index = as_index(value);
  if (!index) refuse(name, range, value);
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < low || v > high) refuse(name, range, value);
  return v;
}

std::uint64_t seed_of(const py::handle& value, const std::string& name) {
  const std::string range = "an integer in [0, 2**64 - 1]";
  const py::object index = as_index(value);
  if (!index) refuse(name, range, value);
  const unsigned long long v = PyLong_AsUnsignedLongLong(index.ptr());
  if (PyErr_Occurred() != nullptr) {
    PyErr_Clear();
    refuse(name, range, value);
  }
  return static_cast<std::uint64_t>(v);
}

double number_in(const py::handle& value, const std::string& name, double low, double high) {
  const std::string range = "a number in [" + py::repr(py::float_(low)).cast<std::string>() + ", " +
                            py::repr(py::float_(high)).cast<std::string>() + "]";
  if (PyBool_Check(value.ptr())) refuse(name, range, value);
  const double v = PyFloat_AsDouble(value.ptr());
  if (PyErr_Occurred() != nullptr) {
    PyErr_Clear();
    refuse(name, range, value);
  }
  if (!(v >= low && v <= high)) refuse(name, range, value);
  return v;
}

} // namespace sodaevo::python
