// Bad input becomes sodaevo.InputError (python/sodaevo/_errors.py), a ValueError
// that carries the message's file, line, column or JSON pointer; never a crash.
// The class lives in pure Python so that it can be documented and subclassed
// like any other; it is looked up when an error is raised.
#include <exception>

#include "core/input_error.hpp"
#include "evolve/problems/wire_format.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

void raise_input_error(const char* message) {
  const py::object type = py::module_::import("sodaevo._errors").attr("InputError");
  const py::object error = type(py::str(message));
  PyErr_SetObject(type.ptr(), error.ptr());
}

} // namespace

void bind_errors(py::module_& /*m*/) {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const soda::InputError& e) {
      raise_input_error(e.what());
    } catch (const WireError& e) {
      raise_input_error(e.what());
    }
  });
}

void warn_all(const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const std::string& w : warnings) warn(py::str(w), py::module_::import("builtins").attr("UserWarning"), 2);
}

} // namespace sodaevo::python
