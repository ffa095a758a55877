// sodaevo.Optimiser: the project's own GA and MAP-Elites as ask/tell. The run's
// loop (run_evolution, run_map_elites) drives a run folder exactly as `sodaevo
// evolve` does, on a thread of its own, with a HandoffEvaluator
// (evolve/evaluators/handoff_evaluator.hpp) as its evaluator: ask() waits until
// the loop needs an evaluation and returns it as an EvaluationRequest (creatures,
// problem, estimator); evaluate(request) scores it on this process's threads;
// tell(results) hands the evaluations back, bit for bit (the wire format), and
// the loop goes on. So the folder is the command's, byte for byte, whoever
// evaluates. At the end the champions are checked on fresh replicas as the
// command checks them.
#include <cmath>
#include <cstdint>
#include <exception>
#include <mutex>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/evaluators/handoff_evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/map_elites_run.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/problems/wire_format.hpp"
#include "python/arguments.hpp"
#include "python/bindings.hpp"
#include "python/interruptible.hpp"

namespace sodaevo::python {

namespace {

py::object finite_or_none(double v) { return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none()); }

} // namespace

py::dict generation_progress(const Progress& p) {
  py::dict d;
  d["algorithm"] = "ga";
  d["generation"] = p.generation;
  d["generations"] = p.generations;
  d["evaluations"] = p.stats.evaluations;
  d["best"] = finite_or_none(p.stats.best);
  d["mean"] = finite_or_none(p.stats.mean);
  d["median"] = finite_or_none(p.stats.median);
  d["worst"] = finite_or_none(p.stats.worst);
  d["invalid"] = p.stats.invalid;
  d["diverged"] = p.stats.diverged;
  return d;
}

namespace {

py::dict iteration_progress(const MapElitesProgress& p) {
  py::dict d;
  d["algorithm"] = "map-elites";
  d["iteration"] = p.iteration;
  d["iterations"] = p.iterations;
  d["evaluations"] = p.evaluations;
  d["rollouts"] = p.rollouts;
  d["filled"] = p.metrics.filled;
  d["cells"] = p.metrics.cells;
  d["qd_score"] = p.metrics.qd_score;
  d["best"] = finite_or_none(p.metrics.best);
  return d;
}

class Optimiser {
 public:
  Optimiser(const py::object& config_spec, const std::string& out, bool force, const py::object& threads,
            const std::string& command_line)
      : threads_(static_cast<int>(integer_in(threads, "threads", 0, kMaxThreads))) {
    const std::shared_ptr<const ParsedConfig> parsed = config_of(config_spec, true);
    config_ = parsed->run;
    store_.emplace(start_run(config_, parsed->source, out, force, command_line));
  }
  Optimiser(const Optimiser&) = delete;
  Optimiser& operator=(const Optimiser&) = delete;

  /// An abandoned run (the object dropped before the end) stops where its loop
  /// waits; its folder is left as after its last checkpoint.
  ~Optimiser() {
    if (!loop_.joinable()) return;
    evaluator_.abandon();
    loop_.join();
  }

  /// The next request, or None once the run is over (its champions checked).
  py::object ask() {
    if (finished_) return py::none();
    if (request_) return py::cast(*request_); // asked again before being told: the same request
    if (!loop_.joinable()) loop_ = std::thread([this] { run_loop(); });
    std::optional<HandoffEvaluator::Request> posted;
    {
      const py::gil_scoped_release free_python; // the loop only varies and saves until it asks
      posted = evaluator_.wait_for_request();
    }
    if (posted) {
      request_ = make_request(std::move(*posted));
      return py::cast(*request_);
    }
    loop_.join();
    finished_ = true;
    if (loop_error_) std::rethrow_exception(loop_error_);
    finish();
    return py::none();
  }

  void tell(long long request, const py::bytes& wire) {
    if (!request_) throw soda::InputError("tell: nothing was asked (call ask() first)");
    if (request != request_->id) {
      throw soda::InputError("tell: these evaluations answer request " + std::to_string(request) +
                             ", the pending request is " + std::to_string(request_->id) +
                             " (evaluate the request ask() returned)");
    }
    const std::string bytes = wire;
    std::vector<Evaluation> evaluations = decode_evaluations(bytes.data(), bytes.size());
    if (evaluations.size() != request_->creatures.size()) {
      throw soda::InputError("tell: " + std::to_string(evaluations.size()) + " evaluations for a request of " +
                             std::to_string(request_->creatures.size()) + " creatures");
    }
    evaluator_.answer(std::move(evaluations));
    request_.reset();
  }

  /// Progress dicts of the generations (iterations) finished since the last call.
  py::list take_progress() {
    std::vector<Progress> generations;
    std::vector<MapElitesProgress> iterations;
    {
      const std::lock_guard lock(progress_mutex_);
      generations.swap(generations_);
      iterations.swap(iterations_);
    }
    py::list out;
    for (const Progress& p : generations) out.append(generation_progress(p));
    for (const MapElitesProgress& p : iterations) out.append(iteration_progress(p));
    return out;
  }

  [[nodiscard]] bool done() const { return finished_; }
  [[nodiscard]] std::string dir() const { return store_->dir().string(); }

  [[nodiscard]] py::dict result() const {
    py::dict r;
    r["run"] = dir();
    r["finished"] = finished_;
    r["stopped_because"] = finished_ ? stop_reason_name(stopped_because_) : std::string();
    if (config_.algorithm == AlgorithmKind::MapElites) {
      r["filled"] = filled_;
    } else {
      r["best_id"] = best_id_;
      r["best_fitness"] = finite_or_none(best_fitness_);
    }
    return r;
  }

 private:
  /// The run's loop, on its own thread, as `sodaevo evolve` runs it; every
  /// evaluation it needs is handed to ask() by the evaluator.
  void run_loop() {
    try {
      if (config_.algorithm == AlgorithmKind::MapElites) {
        MapElitesOptions options;
        options.on_iteration = [&](const MapElitesProgress& p) {
          const std::lock_guard lock(progress_mutex_);
          iterations_.push_back(p);
        };
        const MapElitesOutcome o = run_map_elites(store_->dir(), config_, config_.map_elites, evaluator_, options);
        stopped_because_ = o.stopped_because;
        filled_ = o.metrics.filled;
      } else {
        EvolutionOptions options;
        options.on_generation = [&](const Progress& p) {
          const std::lock_guard lock(progress_mutex_);
          generations_.push_back(p);
        };
        const EvolutionOutcome o = run_evolution(*store_, evaluator_, options);
        stopped_because_ = o.stopped_because;
        best_fitness_ = o.best_fitness;
        best_id_ = o.best_id;
      }
    } catch (const RunAbandoned&) {
    } catch (...) {
      loop_error_ = std::current_exception();
    }
    evaluator_.loop_ended();
  }

  EvaluationRequest make_request(HandoffEvaluator::Request posted) {
    WireReader reader(posted.head.data(), posted.head.size());
    EvaluationRequest r;
    r.problem = read_problem(reader);
    r.estimator = read_estimator(reader);
    r.creatures = std::move(posted.creatures);
    r.id = ++requests_;
    return r;
  }

  /// As `sodaevo evolve` ends a run: the champions (the archive) checked again
  /// on fresh replicas, on this process's threads (Ctrl-C stops it).
  void finish() {
    const std::filesystem::path run = store_->dir();
    const int threads = threads_;
    if (config_.algorithm == AlgorithmKind::MapElites) {
      if (config_.map_elites.check_replicas > 0 && filled_ > 0) {
        run_interruptibly([&] { return write_checked_archive(run, threads); });
      }
    } else if (std::isfinite(best_fitness_)) {
      run_interruptibly([&] {
        return write_run_champions(run, kRunChampionsChecked, kRunChampionReplicas, threads);
      });
    }
  }

  int threads_;
  RunConfig config_;
  std::optional<RunStore> store_;
  HandoffEvaluator evaluator_;
  std::thread loop_;
  std::exception_ptr loop_error_;
  std::optional<EvaluationRequest> request_;
  long long requests_ = 0;
  std::mutex progress_mutex_;
  std::vector<Progress> generations_;
  std::vector<MapElitesProgress> iterations_;
  bool finished_ = false;
  // Written by the loop's thread before it ends, read after it is joined.
  StopReason stopped_because_ = StopReason::Completed;
  std::string best_id_;
  double best_fitness_ = kWorstFitness;
  std::size_t filled_ = 0;
};

} // namespace

void bind_optimiser(py::module_& m) {
  py::class_<EvaluationRequest>(m, "Request",
                                "Creatures an optimiser asks to have evaluated, with the problem and estimator\n"
                                "its run evaluates them with: hand it to sodaevo.evaluate.")
      .def_property_readonly("models", [](const EvaluationRequest& r) { return r.creatures; })
      .def_property_readonly("id", [](const EvaluationRequest& r) { return r.id; })
      .def("__len__", [](const EvaluationRequest& r) { return r.creatures.size(); })
      .def("__getitem__",
           [](const EvaluationRequest& r, std::size_t i) {
             if (i >= r.creatures.size()) throw py::index_error("request index out of range");
             return r.creatures[i];
           })
      .def("__repr__", [](const EvaluationRequest& r) {
        return "<sodaevo.Request " + std::to_string(r.id) + ": " + std::to_string(r.creatures.size()) +
               " creatures, " + r.problem->kind() + ">";
      });
  py::class_<Optimiser>(m, "Optimiser")
      .def(py::init<const py::object&, const std::string&, bool, const py::object&, const std::string&>(),
           py::arg("config"), py::arg("out"), py::kw_only(), py::arg("force") = false, py::arg("threads") = 0,
           py::arg("command_line") = "sodaevo.Optimiser()")
      .def("ask", &Optimiser::ask)
      .def("tell", &Optimiser::tell, py::arg("request"), py::arg("wire"))
      .def("take_progress", &Optimiser::take_progress)
      .def_property_readonly("done", &Optimiser::done)
      .def_property_readonly("dir", &Optimiser::dir)
      .def_property_readonly("result", &Optimiser::result);
}

} // namespace sodaevo::python
