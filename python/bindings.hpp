// The Python module's pieces (python/*.cpp, one concept each), declared for
// module.cpp, and the helpers they share: configs given as a dict or a path, and
// Python warnings for a reader's warnings.
#pragma once

#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "core/model_def.hpp"
#include "evolve/run_config.hpp"

namespace sodaevo::python {

namespace py = pybind11;

void bind_errors(py::module_& m);
void bind_model(py::module_& m);
void bind_simulate(py::module_& m);
void bind_evaluate(py::module_& m);
void bind_race(py::module_& m);
void bind_evolve(py::module_& m);

/// A run config from Python: None (every default), a dict (the JSON object; seed
/// paths relative to the working directory) or a path to a config file (read as
/// `evolve` reads it). Errors are soda::InputError naming "<dict>" or the file.
/// Unless `whole_run`, a dict without seed models needs no
/// /population/random_fraction (settings for an operator or a problem).
RunConfig run_config_of(const py::object& config, bool whole_run = false);

/// The model a Python argument holds (a sodaevo.Model).
const soda::ModelDef& model_of(const py::handle& model);

/// Issues each line as a Python UserWarning (a reader's clamps and notes).
void warn_all(const std::vector<std::string>& warnings);

} // namespace sodaevo::python
