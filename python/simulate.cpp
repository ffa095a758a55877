// sodaevo.simulate: one model run as `sodaevo simulate` runs it (the same library
// call, core/simulation_run.hpp), its summary as the command's --json keys, and
// with trace=True every frame's free masses as an (frames + 1, masses, 4) array of
// x, y, vx, vy: the numbers of `simulate --trace`, bit for bit. With replicas=K
// the distribution over K sine-jitter replicas, as `simulate --replicas K`.
// Ctrl-C stops a run within a fraction of a second (python/interruptible.hpp).
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/fixed_bars.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/simulation_run.hpp"
#include "core/stepping.hpp"
#include "evolve/estimators/replica_ensemble.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "python/arguments.hpp"
#include "python/bindings.hpp"
#include "python/interruptible.hpp"

namespace sodaevo::python {

namespace {

/// Most frames one simulate call runs (the command line's --frames range).
constexpr long long kMaxSimulateFrames = 1'000'000'000'000LL;
/// Largest trace simulate(trace=True) makes: checked before anything is allocated.
constexpr std::size_t kMaxTraceBytes = std::size_t{4} << 30;

soda::BarEngine bar_engine_named(const std::string& name) {
  soda::BarEngine engine{};
  if (!soda::parse_bar_engine(name, engine)) {
    throw soda::InputError("bar_engine: expected 2003 or 2004, got '" + name + "'");
  }
  return engine;
}

/// An owned buffer handed to numpy without a copy.
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free_when_done);
}

py::dict simulate_once(const soda::ModelDef& def, long long frames, bool want_trace, const soda::Stepping& stepping,
                       soda::BarEngine bar_engine, bool energy_check, bool reference) {
  const soda::Model model = soda::build_model(def, bar_engine);
  soda::State state = soda::make_state(model);
  const std::size_t masses = static_cast<std::size_t>(model.mass_count);
  std::vector<double> trace, phases;
  std::vector<int> modes;
  auto record = [&](const soda::State& s) {
    for (std::size_t i = 0; i < masses; ++i) {
      trace.insert(trace.end(), {s.x[i], s.y[i], s.vx[i], s.vy[i]});
    }
    phases.push_back(s.wave_phase);
    modes.push_back(static_cast<int>(s.wave_mode));
  };
  soda::FrameCallback per_frame;
  if (want_trace) {
    const double bytes = (static_cast<double>(frames) + 1) * static_cast<double>(masses) * 4 * sizeof(double);
    if (bytes > kMaxTraceBytes) {
      throw soda::InputError("trace: " + std::to_string(frames + 1) + " frames x " + std::to_string(masses) +
                             " masses x 4 doubles would take " + std::to_string(bytes / (1 << 20)) +
                             " MiB, more than the " + std::to_string(kMaxTraceBytes >> 20) +
                             " MiB a trace may take (ask for fewer frames)");
    }
    trace.reserve((static_cast<std::size_t>(frames) + 1) * masses * 4);
    record(state);
    per_frame = record;
  }
  const soda::Point2 start = soda::mass_centroid(model, state);
  soda::Divergence divergence;
  double seconds = 0.0;
  {
    const auto t0 = std::chrono::steady_clock::now();
    divergence = run_interruptibly(
        [&] { return soda::run_simulation(model, state, frames, stepping, energy_check, reference, per_frame); });
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const soda::Point2 end = soda::mass_centroid(model, state);
  const long long run = divergence.diverged ? divergence.frame - 1 : frames;
  py::dict out;
  out["frames"] = run;
  out["masses"] = model.mass_count;
  out["links"] = model.link_count();
  out["centroid_dx"] = end.x - start.x;
  out["centroid_dy"] = end.y - start.y;
  out["px_per_frame"] = run > 0 ? (end.x - start.x) / static_cast<double>(run) : 0.0;
  out["wall_seconds"] = seconds;
  out["frames_per_second"] = seconds > 0 ? static_cast<double>(run) / seconds : 0.0;
  out["stepping"] = soda::stepping_label(stepping);
  out["fixed_bars"] = model.bar_count();
  out["bar_engine"] = soda::bar_engine_name(bar_engine);
  out["diverged"] = divergence.diverged;
  if (divergence.diverged) {
    out["diverged_frame"] = divergence.frame;
    out["diverged_reason"] = divergence.reason;
  }
  if (want_trace) {
    const auto rows = static_cast<py::ssize_t>(phases.size());
    out["trace"] = to_numpy(std::move(trace), {rows, static_cast<py::ssize_t>(masses), 4});
    out["wave_phase"] = to_numpy(std::move(phases), {rows});
    out["wave_mode"] = to_numpy(std::move(modes), {rows});
  }
  return out;
}

py::dict simulate_replicas(const soda::ModelDef& def, long long frames, int replicas, double jitter, long long settle,
                           const soda::Stepping& stepping, soda::BarEngine bar_engine) {
  const soda::Model model = soda::build_model(def, bar_engine);
  ReplicaSettings settings;
  settings.seeds = consecutive_seeds(replicas);
  settings.probability = jitter;
  settings.settle = settle;
  settings.frames = frames;
  settings.stepping = stepping;
  ReplicaResults r = run_interruptibly([&] { return run_replicas(model, settings); });
  std::vector<double> finite;
  for (double d : r.distances) {
    if (std::isfinite(d)) finite.push_back(d);
  }
  if (finite.empty()) throw soda::InputError("every replica's run turned non-finite (the model blows up)");
  const SampleSummary s = summarize_sample(finite);
  py::dict out;
  out["stepping"] = soda::stepping_label(stepping);
  out["replicas"] = replicas;
  out["jitter"] = jitter;
  out["settle"] = settle;
  out["frames"] = frames;
  out["n"] = s.n;
  out["mean"] = s.mean;
  out["median"] = s.median;
  out["sd"] = s.sd;
  out["min"] = s.min;
  out["max"] = s.max;
  out["interval95"] = py::make_tuple(s.interval95_low, s.interval95_high);
  out["non_finite"] = static_cast<int>(r.distances.size() - finite.size());
  const auto count = static_cast<py::ssize_t>(r.distances.size());
  out["distances"] = to_numpy(std::move(r.distances), {count});
  out["horizon"] = r.horizon >= 0 ? py::object(py::int_(r.horizon)) : py::object(py::none());
  return out;
}

} // namespace

void bind_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](const py::object& model, const py::object& frames_arg, bool trace, const py::object& replicas_arg,
         const std::string& mode, const std::string& integrator, const py::object& substeps,
         const std::string& bar_engine, bool energy_check, bool reference, const py::object& jitter_arg,
         const py::object& settle_arg) {
        const long long frames = integer_in(frames_arg, "frames", 0, kMaxSimulateFrames);
        const soda::ModelDef def = model_of(model);
        const soda::Stepping stepping =
            soda::stepping_of_names(mode, integrator, static_cast<int>(integer_in(substeps, "substeps", 1, 1000000)), "");
        const soda::BarEngine engine = bar_engine_named(bar_engine);
        const int replicas = static_cast<int>(integer_in(replicas_arg, "replicas", 0, 10000));
        if (replicas > 0) {
          if (trace) throw soda::InputError("trace: a trace is of one run, not of replicas (replicas=0)");
          const double jitter = number_in(jitter_arg, "jitter", 0.0, 1.0);
          const long long settle = integer_in(settle_arg, "settle", 0, kMaxSimulateFrames);
          return simulate_replicas(def, frames, replicas, jitter, settle, stepping, engine);
        }
        return simulate_once(def, frames, trace, stepping, engine, energy_check, reference);
      },
      py::arg("model"), py::arg("frames") = 1000, py::kw_only(), py::arg("trace") = false, py::arg("replicas") = 0,
      py::arg("mode") = "soda", py::arg("integrator") = "euler", py::arg("substeps") = 1,
      py::arg("bar_engine") = "2003", py::arg("energy_check") = false, py::arg("reference") = false,
      py::arg("jitter") = 0.002, py::arg("settle") = 0);
}

} // namespace sodaevo::python
