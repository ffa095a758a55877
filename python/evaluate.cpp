// sodaevo.evaluate: a list of creatures evaluated as `evolve` evaluates a
// generation: the run config's Problem (walk or race, its /fitness object), a
// ReplicaEstimator on its replicas, and a ThreadEvaluator that hands batches of
// creatures to N threads, each batch stepped fused on one core. The GIL is
// released for the whole batch. Also the config helpers the other pieces share.
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/replica_estimator.hpp"
#include "evolve/run_roles.hpp"
#include "evolve/sample_summary.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

RunConfig run_config_of(const py::object& config, bool whole_run) {
  if (config.is_none()) return RunConfig{};
  if (py::isinstance<py::dict>(config)) {
    py::dict given = py::module_::import("copy").attr("deepcopy")(config);
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
    const std::string text = py::module_::import("json").attr("dumps")(given, py::arg("allow_nan") = false).cast<std::string>();
    return parse_run_config(text, "<dict>", std::filesystem::current_path());
  }
  const py::object path = py::module_::import("os").attr("fspath")(config);
  return read_run_config(path.cast<std::string>());
}

namespace {

/// The config of evaluate(): a whole run config (a path, or a dict with a
/// "fitness" key) or the /fitness object alone.
RunConfig problem_config(const py::object& problem) {
  if (py::isinstance<py::dict>(problem) && !problem.cast<py::dict>().contains("fitness")) {
    py::dict whole;
    whole["fitness"] = problem;
    return run_config_of(whole);
  }
  return run_config_of(problem);
}

py::dict evaluate(const py::sequence& models, const py::object& problem_spec, const py::object& replicas,
                  const py::object& seed, int threads, std::size_t batch) {
  RunConfig config = problem_config(problem_spec);
  if (!replicas.is_none()) {
    const int k = replicas.cast<int>();
    if (k < 1 || k > 256) throw soda::InputError("replicas: expected an integer in [1, 256], got " + std::to_string(k));
    config.fitness.replicas = k;
    config.fitness.replicas_max = std::max(config.fitness.replicas_max, k);
  }
  if (!seed.is_none()) config.seed = seed.cast<std::uint64_t>();
  if (threads < 0) throw soda::InputError("threads: expected an integer >= 0 (0: all cores), got " + std::to_string(threads));
  // Copies: the batch runs without the GIL, so it holds nothing Python owns.
  std::vector<soda::ModelDef> creatures;
  creatures.reserve(models.size());
  for (const py::handle& m : models) creatures.push_back(model_of(m));
  std::vector<const soda::ModelDef*> pointers;
  for (const soda::ModelDef& c : creatures) pointers.push_back(&c);
  const std::unique_ptr<Problem> problem = problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  std::vector<Evaluation> results;
  {
    py::gil_scoped_release free_python;
    ThreadEvaluator evaluator(threads, batch);
    results = evaluator.evaluate(pointers, *problem, estimator);
  }
  const auto n = static_cast<py::ssize_t>(results.size());
  py::array_t<double> fitness(n), distance(n), px_per_frame(n), mean(n), sd(n), median(n);
  py::array_t<int> rollouts(n);
  py::array_t<double> interval({n, py::ssize_t{2}});
  auto f = fitness.mutable_unchecked<1>(), d = distance.mutable_unchecked<1>(), p = px_per_frame.mutable_unchecked<1>(),
       me = mean.mutable_unchecked<1>(), s = sd.mutable_unchecked<1>(), md = median.mutable_unchecked<1>();
  auto k = rollouts.mutable_unchecked<1>();
  auto iv = interval.mutable_unchecked<2>();
  py::list status, reason;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (py::ssize_t i = 0; i < n; ++i) {
    const Evaluation& e = results[static_cast<std::size_t>(i)];
    const bool ok = e.ok();
    f(i) = e.fitness;
    d(i) = ok ? e.distance : nan;
    p(i) = ok ? e.px_per_frame : nan;
    k(i) = e.estimate.rollouts;
    me(i) = ok ? e.estimate.mean : nan;
    s(i) = ok ? e.estimate.sd : nan;
    md(i) = ok ? e.estimate.median : nan;
    const double half = prediction_half_width95(e.estimate.rollouts, e.estimate.sd);
    iv(i, 0) = ok ? e.estimate.mean - half : nan;
    iv(i, 1) = ok ? e.estimate.mean + half : nan;
    status.append(status_name(e.status));
    reason.append(e.reason);
  }
  py::dict out;
  out["fitness"] = fitness;
  out["distance"] = distance;
  out["px_per_frame"] = px_per_frame;
  out["n"] = rollouts;
  out["mean"] = mean;
  out["sd"] = sd;
  out["median"] = median;
  out["interval95"] = interval;
  out["status"] = status;
  out["reason"] = reason;
  return out;
}

} // namespace

void bind_evaluate(py::module_& m) {
  m.def("evaluate", &evaluate, py::arg("models"), py::arg("problem") = py::dict(), py::kw_only(),
        py::arg("replicas") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = 0, py::arg("batch") = 0);
}

} // namespace sodaevo::python
