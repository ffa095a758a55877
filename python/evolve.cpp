// sodaevo.evolve and the run store from Python: a whole GA run into a run folder
// as `sodaevo evolve` makes it (start_run, run_evolution, the champions' check:
// evolve/runs/evolution_run.hpp), saved generations read back as Models, and the GA's
// own variation operators (evolve/algorithms/variation.hpp) for outside algorithms.
#include <atomic>
#include <memory>
#include <optional>
#include <cmath>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/algorithms/variation.hpp"
#include "python/arguments.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

/// The config an operator is given: a sodaevo.Config's without a copy or a
/// parse, the defaults for None, else the dict or file parsed.
class OperatorConfig {
 public:
  explicit OperatorConfig(const py::object& spec) {
    if (py::isinstance<ParsedConfig>(spec)) parsed_ = spec.cast<std::shared_ptr<ParsedConfig>>();
    else if (!spec.is_none()) own_ = run_config_of(spec);
  }
  [[nodiscard]] const RunConfig& get() const { return parsed_ ? parsed_->run : own_; }

 private:
  std::shared_ptr<const ParsedConfig> parsed_;
  RunConfig own_;
};

/// An individual of a saved generation as a dict; its genome a sodaevo.Model.
py::dict individual_dict(const Individual& ind) {
  py::dict d;
  d["id"] = ind.id;
  d["parents"] = ind.parents;
  d["model"] = ind.creature;
  d["status"] = status_name(ind.evaluation.status);
  d["reason"] = ind.evaluation.reason;
  d["fitness"] = ind.evaluation.fitness;
  d["distance"] = ind.evaluation.distance;
  d["n"] = ind.evaluation.estimate.rollouts;
  d["mean"] = ind.evaluation.estimate.mean;
  d["sd"] = ind.evaluation.estimate.sd;
  d["median"] = ind.evaluation.estimate.median;
  return d;
}

std::string run_evolve(const py::object& config_spec, const std::string& out, const py::object& threads_arg, bool force,
                       const std::string& command_line, const py::object& callback) {
  const int threads = static_cast<int>(integer_in(threads_arg, "threads", 0, kMaxThreads));
  const std::shared_ptr<const ParsedConfig> parsed = config_of(config_spec, true);
  const RunConfig& config = parsed->run;
  if (config.algorithm != AlgorithmKind::Genetic) {
    throw soda::InputError("/algorithm: expected \"ga\" from Python, got \"map-elites\" (run MAP-Elites with "
                           "`sodaevo evolve CONFIG`; open_run reads its folder)");
  }
  RunStore store = start_run(config, parsed->source, out, force, command_line);
  ThreadEvaluator evaluator(threads);
  // Ctrl-C: the current generation is finished and saved, then KeyboardInterrupt.
  // An exception of the callback stops the run the same way and is raised.
  std::atomic<bool> stop{false};
  bool interrupted = false;
  std::optional<py::error_already_set> callback_error;
  EvolutionOptions options;
  options.stop_requested = &stop;
  options.on_generation = [&](const Progress& p) {
    py::gil_scoped_acquire python;
    if (!callback.is_none() && !callback_error) {
      try {
        callback(generation_progress(p));
      } catch (py::error_already_set& e) {
        callback_error.emplace(std::move(e));
        stop = true;
      }
    }
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      interrupted = true;
      stop = true;
    }
  };
  EvolutionOutcome outcome;
  {
    py::gil_scoped_release free_python;
    outcome = run_evolution(store, evaluator, options);
    if (std::isfinite(outcome.best_fitness)) {
      write_run_champions(store.dir(), kRunChampionsChecked, kRunChampionReplicas, threads);
    }
  }
  if (callback_error) throw std::move(*callback_error);
  if (interrupted) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  return store.dir().string();
}

} // namespace

void bind_evolve(py::module_& m) {
  m.def("evolve", &run_evolve, py::arg("config"), py::arg("out"), py::kw_only(), py::arg("threads") = 0,
        py::arg("force") = false, py::arg("command_line") = "sodaevo.evolve()", py::arg("callback") = py::none());
  m.def("saved_generations", [](const std::string& run) { return saved_generations(run); }, py::arg("run"));
  m.def(
      "read_generation",
      [](const std::string& run, int generation) {
        const Generation g = read_saved_generation(run, generation);
        py::list out;
        for (const Individual& ind : g.individuals) out.append(individual_dict(ind));
        return out;
      },
      py::arg("run"), py::arg("generation"));
  m.def(
      "best_individuals",
      [](const std::string& run, int count) {
        py::list out;
        for (const Individual& ind : best_individuals(run, count)) out.append(individual_dict(ind));
        return out;
      },
      py::arg("run"), py::arg("count"));
  m.def(
      "mutate",
      [](const py::object& model, const py::object& rng_seed, const py::object& config) {
        const OperatorConfig c(config);
        soda::ModelDef child = model_of(model);
        Rng rng = Rng::stream(seed_of(rng_seed, "rng_seed"), 0);
        mutate(child, c.get(), rng);
        return child;
      },
      py::arg("model"), py::arg("rng_seed"), py::arg("config") = py::none());
  m.def(
      "crossover",
      [](const py::object& a, const py::object& b, const py::object& rng_seed, const py::object& config) {
        const OperatorConfig c(config);
        Rng rng = Rng::stream(seed_of(rng_seed, "rng_seed"), 0);
        return crossover(model_of(a), model_of(b), c.get(), rng);
      },
      py::arg("a"), py::arg("b"), py::arg("rng_seed"), py::arg("config") = py::none());
  m.def(
      "random_creature",
      [](const py::object& rng_seed, const py::object& config) {
        const OperatorConfig c(config);
        Rng rng = Rng::stream(seed_of(rng_seed, "rng_seed"), 0);
        return random_creature(c.get(), rng);
      },
      py::arg("rng_seed"), py::arg("config") = py::none());
  m.def(
      "creature",
      [](const py::object& model, const py::object& config) {
        const OperatorConfig c(config);
        return creature_from_seed(model_of(model), c.get());
      },
      py::arg("model"), py::arg("config") = py::none());
}

} // namespace sodaevo::python
