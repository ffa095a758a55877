// sodaevo.Config: a run config parsed once (the reader's checks and messages),
// with its Problem and ReplicaEstimator built once, so that evaluate, mutate,
// crossover and the optimiser reuse it instead of reading a config per call.
// Seed-model paths are resolved when it is made: a file's against the file's
// folder (as `sodaevo evolve` does), a dict's against `base` (default: the
// working directory). Also run_config_of / config_of, which every other piece
// uses for a config argument (a Config, a dict, a path or None).
#include <filesystem>
#include <memory>
#include <string>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "core/input_error.hpp"
#include "evolve/runs/run_roles.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

/// The JSON text of a dict: numpy numbers and arrays as plain numbers and lists.
std::string json_text_of(const py::dict& config) {
  const py::object dumps = py::module_::import("json").attr("dumps");
  const py::object plain = py::module_::import("sodaevo._plain").attr("plain_json_value");
  return dumps(config, py::arg("allow_nan") = false, py::arg("default") = plain).cast<std::string>();
}

RunConfig parse_dict(py::dict given, bool whole_run, const std::filesystem::path& base) {
  given = py::module_::import("copy").attr("deepcopy")(given);
  if (!whole_run) {
    // Settings for an operator or a problem, not a run: without seed models
    // every creature is one's own, so no population's share of random
    // creatures is asked for (a run's config must give it).
    py::dict population = given.contains("population") ? py::dict(given["population"]) : py::dict();
    if (!population.contains("seed_models") && !population.contains("random_fraction")) {
      population["random_fraction"] = 1;
      given["population"] = population;
    }
  }
  return parse_run_config(json_text_of(given), "<dict>", base);
}

std::shared_ptr<const ParsedConfig> parse(const py::object& spec, bool whole_run, bool fitness_alone,
                                          const py::object& base) {
  const std::filesystem::path base_dir =
      base.is_none() ? std::filesystem::current_path()
                     : std::filesystem::path(py::module_::import("os").attr("fspath")(base).cast<std::string>());
  if (spec.is_none()) return make_parsed(RunConfig{}, "<defaults>");
  if (py::isinstance<py::dict>(spec)) {
    py::dict given = spec.cast<py::dict>();
    if (fitness_alone && !given.contains("fitness")) {
      py::dict whole;
      whole["fitness"] = given;
      given = whole;
    }
    return make_parsed(parse_dict(given, whole_run, base_dir), "<dict>");
  }
  if (py::isinstance<py::str>(spec) || py::hasattr(spec, "__fspath__")) {
    const std::string path = py::module_::import("os").attr("fspath")(spec).cast<std::string>();
    return make_parsed(read_run_config(path), path);
  }
  throw py::type_error("config: expected a sodaevo.Config, a dict, a path or None, got " +
                       py::str(py::type::of(spec).attr("__name__")).cast<std::string>());
}

} // namespace

std::shared_ptr<const ParsedConfig> make_parsed(RunConfig run, std::string source) {
  auto parsed = std::make_shared<ParsedConfig>();
  parsed->problem = problem_of(run);
  parsed->estimator = std::make_shared<const ReplicaEstimator>(replica_plan(run));
  parsed->run = std::move(run);
  parsed->source = std::move(source);
  return parsed;
}

std::shared_ptr<const ParsedConfig> config_of(const py::object& spec, bool whole_run, bool fitness_alone) {
  if (py::isinstance<ParsedConfig>(spec)) return spec.cast<std::shared_ptr<ParsedConfig>>();
  return parse(spec, whole_run, fitness_alone, py::none());
}

RunConfig run_config_of(const py::object& config, bool whole_run) {
  if (py::isinstance<ParsedConfig>(config)) return config.cast<const ParsedConfig&>().run;
  if (config.is_none()) return RunConfig{};
  return config_of(config, whole_run)->run;
}

void bind_config(py::module_& m) {
  py::class_<ParsedConfig, std::shared_ptr<ParsedConfig>>(m, "Config",
      "A run config parsed once: evaluate, mutate, crossover, random_creature and the\n"
      "optimiser take it instead of a dict or path and then read nothing again.")
      .def(py::init([](const py::object& spec, const py::object& base, bool fitness_alone) {
             return std::const_pointer_cast<ParsedConfig>(parse(spec, true, fitness_alone, base));
           }),
           py::arg("config") = py::none(), py::kw_only(), py::arg("base") = py::none(),
           py::arg("fitness_alone") = false,
           "config: a config file's path (seed models relative to its folder), a dict (relative\n"
           "to `base`, default the working directory) or None (every default).\n"
           "fitness_alone=True: a dict without a \"fitness\" key is the /fitness object.")
      .def_property_readonly("source", [](const ParsedConfig& c) { return c.source; },
                             "Where it was read from: the file, \"<dict>\" or \"<defaults>\".")
      .def_property_readonly(
          "dict",
          [](const ParsedConfig& c) {
            return py::module_::import("json").attr("loads")(to_json(c.run).dump());
          },
          "The resolved config as a dict: every key, seed-model paths absolute.")
      .def_property_readonly("name", [](const ParsedConfig& c) { return c.run.name; })
      .def_property_readonly("seed", [](const ParsedConfig& c) { return c.run.seed; })
      .def("__repr__", [](const ParsedConfig& c) { return "<sodaevo.Config '" + c.run.name + "' from " + c.source + ">"; });
}

} // namespace sodaevo::python
