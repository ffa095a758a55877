// sodaevo.evaluate: a list of creatures evaluated as `evolve` evaluates a
// generation: the run config's Problem (walk or race, its /fitness object), a
// ReplicaEstimator on its replicas, and a ThreadEvaluator that hands batches of
// creatures to N threads, each batch stepped fused on one core. The GIL is
// released for the whole batch, and Ctrl-C stops it (python/interruptible.hpp).
// An optimiser's request is evaluated with the problem and estimator its run
// asked for.
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/config/input_limits.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "evolve/problems/wire_format.hpp"
#include "python/arguments.hpp"
#include "python/bindings.hpp"
#include "python/interruptible.hpp"

namespace sodaevo::python {

namespace {

/// Evaluations as evaluate() returns them: numpy arrays, and the wire bytes of
/// every Evaluation (what an optimiser's tell() reads back, exactly).
py::dict evaluations_dict(const std::vector<Evaluation>& results);

/// Copies of the models (the work runs without the GIL, so it holds nothing
/// Python owns).
std::vector<soda::ModelDef> creatures_of(const py::sequence& models) {
  std::vector<soda::ModelDef> creatures;
  creatures.reserve(models.size());
  for (const py::handle& m : models) creatures.push_back(model_of(m));
  return creatures;
}

std::vector<Evaluation> evaluate_on_threads(const std::vector<soda::ModelDef>& creatures, const Problem& problem,
                                            const Estimator& estimator, int threads, std::size_t batch) {
  std::vector<const soda::ModelDef*> pointers;
  for (const soda::ModelDef& c : creatures) pointers.push_back(&c);
  return run_interruptibly([&] {
    ThreadEvaluator evaluator(threads, batch);
    return evaluator.evaluate(pointers, problem, estimator);
  });
}

py::dict evaluate(const py::object& models, const py::object& problem_spec, const py::object& replicas,
                  const py::object& seed, const py::object& threads_arg, const py::object& batch_arg) {
  const int threads = static_cast<int>(integer_in(threads_arg, "threads", 0, kMaxThreads));
  const auto batch = static_cast<std::size_t>(integer_in(batch_arg, "batch", 0, kMaxPopulation));
  if (py::isinstance<EvaluationRequest>(models)) {
    // An optimiser's request: evaluated as its run asks (its problem and estimator).
    if (!replicas.is_none() || !seed.is_none() || !problem_spec.is_none()) {
      throw soda::InputError("problem, replicas, seed: an optimiser's request is evaluated as its run asks; "
                             "give none of them");
    }
    const EvaluationRequest& request = models.cast<const EvaluationRequest&>();
    py::dict out = evaluations_dict(evaluate_on_threads(request.creatures, *request.problem, *request.estimator,
                                                        threads, batch));
    out["request"] = request.id;
    return out;
  }
  if (!py::isinstance<py::sequence>(models) || py::isinstance<py::str>(models)) {
    throw py::type_error("models: expected a sequence of sodaevo.Model or an optimiser's request");
  }
  std::shared_ptr<const ParsedConfig> parsed = config_of(problem_spec, false, true);
  if (!replicas.is_none() || !seed.is_none()) {
    RunConfig config = parsed->run;
    if (!replicas.is_none()) {
      const int k = static_cast<int>(integer_in(replicas, "replicas", 1, 256));
      config.fitness.replicas = k;
      config.fitness.replicas_max = std::max(config.fitness.replicas_max, k);
    }
    if (!seed.is_none()) config.seed = static_cast<std::uint64_t>(integer_in(seed, "seed", 0, 1LL << 53));
    parsed = make_parsed(config, parsed->source);
  }
  const std::vector<soda::ModelDef> creatures = creatures_of(models.cast<py::sequence>());
  return evaluations_dict(evaluate_on_threads(creatures, *parsed->problem, *parsed->estimator, threads, batch));
}

py::dict evaluations_dict(const std::vector<Evaluation>& results) {
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
  const std::vector<char> wire = encode_evaluations(results);
  out["wire"] = py::bytes(wire.data(), wire.size());
  return out;
}

} // namespace

void bind_evaluate(py::module_& m) {
  m.def("evaluate", &evaluate, py::arg("models"), py::arg("problem") = py::none(), py::kw_only(),
        py::arg("replicas") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = 0, py::arg("batch") = 0);
}

} // namespace sodaevo::python
