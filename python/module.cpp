// The extension module sodaevo._sodaevo; python/sodaevo/__init__.py is its
// public face (docstrings, type hints, dataclasses).
#include <pybind11/pybind11.h>

#include "python/bindings.hpp"

PYBIND11_MODULE(_sodaevo, m) {
  m.doc() = "sodaevo's exact SodaConstructor engine, its batches, replicas and run store (use the sodaevo package)";
  m.attr("__version__") = SODAEVO_VERSION; // CMakeLists.txt's project() version, as pip's metadata
  sodaevo::python::bind_errors(m);
  sodaevo::python::bind_model(m);
  sodaevo::python::bind_config(m);
  sodaevo::python::bind_genome(m);
  sodaevo::python::bind_simulate(m);
  sodaevo::python::bind_evaluate(m);
  sodaevo::python::bind_race(m);
  sodaevo::python::bind_evolve(m);
  sodaevo::python::bind_optimiser(m);
}
