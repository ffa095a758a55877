// The Python module's pieces (python/*.cpp, one concept each), declared for
// module.cpp, and the helpers they share: configs given as a dict or a path, and
// Python warnings for a reader's warnings.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "core/model_def.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {
struct Progress;
}

namespace sodaevo::python {

namespace py = pybind11;

void bind_errors(py::module_& m);
void bind_model(py::module_& m);
void bind_simulate(py::module_& m);
void bind_evaluate(py::module_& m);
void bind_race(py::module_& m);
void bind_evolve(py::module_& m);
void bind_config(py::module_& m);
void bind_optimiser(py::module_& m);
void bind_genome(py::module_& m);

/// A run config read once (sodaevo.Config, python/config.cpp) and the roles
/// made of it, reused by every call that is given it.
struct ParsedConfig {
  RunConfig run;
  std::string source; ///< the file, "<dict>" or "<defaults>"
  std::shared_ptr<const Problem> problem;
  std::shared_ptr<const ReplicaEstimator> estimator;
};

/// A GA generation's progress as the optimiser's and evolve()'s callbacks get it.
py::dict generation_progress(const Progress& p);

/// What an optimiser asks to have evaluated (sodaevo's ask(), python/optimiser.cpp):
/// the creatures and the very problem and estimator its run evaluates them with.
struct EvaluationRequest {
  std::vector<soda::ModelDef> creatures;
  std::shared_ptr<const Problem> problem;
  std::shared_ptr<const Estimator> estimator;
  long long id = 0; ///< which request of its optimiser (tell() checks it)
};

/// `run` with its roles built, read from `source`.
std::shared_ptr<const ParsedConfig> make_parsed(RunConfig run, std::string source);

/// A config argument as a ParsedConfig: a sodaevo.Config as it is, else parsed
/// (as run_config_of). `fitness_alone`: a dict without a "fitness" key is the
/// /fitness object (evaluate's `problem`).
std::shared_ptr<const ParsedConfig> config_of(const py::object& config, bool whole_run = false,
                                              bool fitness_alone = false);

/// A run config from Python: None (every default), a sodaevo.Config, a dict (the
/// JSON object, numpy numbers allowed; seed paths relative to the working
/// directory) or a path to a config file (read as `evolve` reads it). Errors are soda::InputError naming "<dict>" or the file.
/// Unless `whole_run`, a dict without seed models needs no
/// /population/random_fraction (settings for an operator or a problem).
RunConfig run_config_of(const py::object& config, bool whole_run = false);

/// The model a Python argument holds (a sodaevo.Model).
const soda::ModelDef& model_of(const py::handle& model);

/// Issues each line as a Python UserWarning (a reader's clamps and notes).
void warn_all(const std::vector<std::string>& warnings);

} // namespace sodaevo::python
