#include "accuracy_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "bench/analytic_scenes.hpp"
#include "bench/median.hpp"
#include "core/divergence.hpp"
#include "core/model.hpp"
#include "core/step_failure.hpp"
#include "evolve/rng.hpp"
#include "evolve/run_config.hpp"
#include "evolve/variation.hpp"
#include "evolve/walk_problem.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::bench {

namespace {

using Clock = std::chrono::steady_clock;

/// Walkers are also ranked by the distance after this many scored frames, where
/// their motion is still predictable (over 1000 frames most random creatures are
/// chaotic: RK4 at 128 and 256 sub-steps disagree).
constexpr long long kShortHorizon = 100;
/// A walker "moves" when its reference centroid walks at least this fast, px/frame.
constexpr double kMoverSpeed = 0.1;

struct RunResult {
  std::vector<std::vector<double>> positions; ///< per checkpoint: x0 y0 x1 y1 ... of the free masses
  double seconds = 0.0;
  bool diverged = false;
};

/// Runs from the initial state to each checkpoint frame (ascending) and records
/// the free masses' positions there.
RunResult run_with_checkpoints(const soda::Model& model, const soda::Stepping& stepping,
                               const std::vector<long long>& checkpoints) {
  RunResult r;
  soda::State s = soda::make_state(model);
  // Soda runs the plain reference step: a scalar loop like the continuous
  // stepper, so that the timings compare methods, not implementations.
  soda::FrameStepper stepper(model, stepping, checkpoints.empty() ? 0 : checkpoints.back(), true);
  long long done = 0;
  const auto t0 = Clock::now();
  for (long long frame : checkpoints) {
    try {
      stepper.run(s, frame - done);
    } catch (const soda::StepFailure&) { // an implicit solve failed: the run counts as diverged
      r.diverged = true;
      r.positions.resize(checkpoints.size(), std::vector<double>(2 * static_cast<std::size_t>(model.mass_count),
                                                                 std::numeric_limits<double>::quiet_NaN()));
      r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      return r;
    }
    done = frame;
    std::vector<double> p;
    p.reserve(2 * static_cast<std::size_t>(model.mass_count));
    for (int i = 0; i < model.mass_count; ++i) {
      p.push_back(s.x[i]);
      p.push_back(s.y[i]);
    }
    r.positions.push_back(std::move(p));
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.diverged = soda::first_non_finite(model, s).has_value();
  return r;
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double d = std::fabs(a[i] - b[i]);
    worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(worst, d);
  }
  return worst;
}

double centroid_x(const std::vector<double>& p) {
  double sx = 0.0;
  for (std::size_t i = 0; i < p.size(); i += 2) sx += p[i];
  return p.empty() ? 0.0 : sx / static_cast<double>(p.size() / 2);
}

double relative_error(double value, double reference) {
  return std::fabs(value - reference) / std::max(std::fabs(reference), 1.0);
}

void say(const AccuracyOptions& o, const std::string& line) {
  if (o.progress) o.progress(line);
}

RunConfig classic_config(const AccuracyOptions& o) {
  RunConfig c;
  c.world.evolve = world_parameter_names(); // keep each classic's own world
  c.fitness.scaling = FitnessScaling::None;
  c.fitness.frames = o.classic_frames;
  c.fitness.settle_frames = o.settle_frames;
  c.limits.max_masses = 10000;
  c.limits.max_links = 100000;
  return c;
}

void analytic_section(const AccuracyOptions& o, const std::vector<soda::Stepping>& settings, AccuracyReport& out) {
  const std::vector<long long> times = {10, 20, 40};
  for (const AnalyticScene& scene : analytic_scenes()) {
    say(o, "analytic: " + scene.name);
    const soda::Model model = soda::build_model(scene.def);
    std::vector<std::vector<double>> truth;
    if (scene.exact) {
      for (long long t : times) truth.push_back(scene.exact(static_cast<double>(t)));
    } else {
      truth = run_with_checkpoints(model, {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 1024}, times).positions;
    }
    for (const soda::Stepping& st : settings) {
      // Tiny scenes: repeat until the timing is measurable; the fastest of a few
      // such batches is the run time (the machine is shared).
      RunResult r;
      double best = std::numeric_limits<double>::infinity();
      for (int batch = 0; batch < o.timing_runs; ++batch) {
        double seconds = 0.0;
        long long frames = 0;
        do {
          r = run_with_checkpoints(model, st, times);
          seconds += r.seconds;
          frames += times.back();
        } while (seconds < (o.quick ? 0.002 : 0.01));
        best = std::min(best, seconds / static_cast<double>(frames));
      }
      AccuracyRow row;
      row.section = "analytic";
      row.scene = scene.name;
      row.stepping = st;
      row.seconds_per_frame = best;
      for (std::size_t k = 0; k < times.size(); ++k) {
        row.position_error = std::max(row.position_error, max_abs_difference(r.positions[k], truth[k]));
      }
      row.diverged = r.diverged ? 1 : 0;
      out.rows.push_back(row);
    }
  }
}

void classic_section(const AccuracyOptions& o, const std::vector<soda::Stepping>& settings, AccuracyReport& out) {
  const RunConfig config = classic_config(o);
  const long long settle = o.settle_frames, end = o.settle_frames + o.classic_frames;
  const long long early = std::min<long long>(100, end);
  std::vector<long long> checkpoints = {early, settle, end};
  std::sort(checkpoints.begin(), checkpoints.end());
  checkpoints.erase(std::unique(checkpoints.begin(), checkpoints.end()), checkpoints.end());
  auto index_of = [&](long long f) {
    return static_cast<std::size_t>(std::find(checkpoints.begin(), checkpoints.end(), f) - checkpoints.begin());
  };
  for (const auto& [name, path] : o.classics) {
    say(o, "classic: " + name);
    const soda::ModelDef creature = creature_from_seed(soda::read_model_file(path).def, config);
    const soda::Model model = soda::build_model(WalkProblem(config).prepare(creature));
    auto distance_of = [&](const RunResult& r) {
      return centroid_x(r.positions[index_of(end)]) - centroid_x(r.positions[index_of(settle)]);
    };
    const soda::Stepping reference{soda::PhysicsMode::Continuous, soda::Integrator::Rk4, o.reference_substeps};
    const RunResult ref = run_with_checkpoints(model, reference, checkpoints);
    const RunResult half_ref = run_with_checkpoints(
        model, {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, o.reference_substeps / 2}, checkpoints);
    const double ref_distance = distance_of(ref);
    if (std::fabs(ref_distance) > 50.0) out.walkers_among_classics.push_back(name);
    out.reference_uncertainty.emplace_back(name, relative_error(distance_of(half_ref), ref_distance));
    for (const soda::Stepping& st : settings) {
      // The machine is shared: the fastest of a few identical runs is the run time.
      RunResult r = run_with_checkpoints(model, st, checkpoints);
      for (int again = 1; again < o.timing_runs; ++again) {
        r.seconds = std::min(r.seconds, run_with_checkpoints(model, st, checkpoints).seconds);
      }
      AccuracyRow row;
      row.section = "classic";
      row.scene = name;
      row.stepping = st;
      row.seconds_per_frame = r.seconds / static_cast<double>(end);
      row.position_error = max_abs_difference(r.positions[index_of(early)], ref.positions[index_of(early)]);
      row.distance = distance_of(r);
      row.reference_distance = ref_distance;
      row.distance_error = relative_error(row.distance, ref_distance);
      row.diverged = r.diverged ? 1 : 0;
      out.rows.push_back(row);
    }
  }
}

void walkers_section(const AccuracyOptions& o, const std::vector<soda::Stepping>& settings, AccuracyReport& out) {
  RunConfig config;
  config.fitness.frames = o.walker_frames;
  config.fitness.settle_frames = o.settle_frames;
  std::vector<soda::Model> models;
  for (std::uint64_t i = 0; static_cast<int>(models.size()) < o.walkers && i < 100ull * o.walkers; ++i) {
    Rng rng = Rng::stream(o.seed, i, 0, 0xacc);
    try {
      models.push_back(soda::build_model(WalkProblem(config).prepare(random_creature(config, rng))));
    } catch (const std::exception&) {
      // e.g. too small to scale within gravity's range: draw another
    }
  }
  const long long settle = o.settle_frames;
  const long long short_end = settle + std::min(kShortHorizon, o.walker_frames);
  const long long end = settle + o.walker_frames;
  const std::vector<long long> checkpoints = {settle, short_end, end};
  struct Distances {
    std::vector<double> full, shorter;
    double seconds = 0.0;
    int diverged = 0;
  };
  auto distances = [&](const soda::Stepping& st) {
    Distances d;
    for (const soda::Model& m : models) {
      const RunResult r = run_with_checkpoints(m, st, checkpoints);
      d.seconds += r.seconds;
      if (r.diverged) ++d.diverged;
      const double worst = -std::numeric_limits<double>::max(); // the GA's rank of a diverged creature
      d.shorter.push_back(r.diverged ? worst : centroid_x(r.positions[1]) - centroid_x(r.positions[0]));
      d.full.push_back(r.diverged ? worst : centroid_x(r.positions[2]) - centroid_x(r.positions[0]));
    }
    return d;
  };
  say(o, "walkers: " + std::to_string(models.size()) + " random creatures, reference");
  const Distances ref = distances({soda::PhysicsMode::Continuous, soda::Integrator::Rk4, o.reference_substeps});
  const Distances half_ref = distances({soda::PhysicsMode::Continuous, soda::Integrator::Rk4, o.reference_substeps / 2});
  out.walkers_noise_floor_tau = kendall_tau(half_ref.full, ref.full);
  out.walkers_noise_floor_tau_short = kendall_tau(half_ref.shorter, ref.shorter);
  // The movers: creatures whose reference walks at least kMoverSpeed. Among the
  // others the ranking is a ranking of jitter.
  std::vector<std::size_t> movers;
  for (std::size_t i = 0; i < ref.full.size(); ++i) {
    if (std::fabs(ref.full[i]) >= kMoverSpeed * static_cast<double>(o.walker_frames)) movers.push_back(i);
  }
  auto subset = [&](const std::vector<double>& v) {
    std::vector<double> out_values;
    for (std::size_t i : movers) out_values.push_back(v[i]);
    return out_values;
  };
  out.walkers_movers = static_cast<int>(movers.size());
  out.walkers_noise_floor_tau_movers = kendall_tau(subset(half_ref.full), subset(ref.full));
  const double frames = static_cast<double>(models.size()) * static_cast<double>(end);
  for (const soda::Stepping& st : settings) {
    say(o, "walkers: " + soda::stepping_label(st));
    AccuracyRow row;
    row.section = "walkers";
    row.scene = std::to_string(models.size()) + " random walkers";
    row.stepping = st;
    const Distances d = distances(st);
    row.diverged = d.diverged;
    row.seconds_per_frame = d.seconds / frames;
    row.kendall_tau = kendall_tau(d.full, ref.full);
    row.kendall_tau_short = kendall_tau(d.shorter, ref.shorter);
    row.kendall_tau_movers = kendall_tau(subset(d.full), subset(ref.full));
    std::vector<double> errors;
    for (std::size_t i = 0; i < d.full.size(); ++i) errors.push_back(relative_error(d.full[i], ref.full[i]));
    row.distance_error = median(errors);
    out.rows.push_back(row);
  }
}

} // namespace

int swept_max_substeps(soda::Integrator integrator) {
  const bool implicit =
      integrator == soda::Integrator::BackwardEuler || integrator == soda::Integrator::ImplicitMidpoint;
  return implicit ? kImplicitMaxSubsteps : soda::kMaxSubsteps;
}

std::vector<soda::Stepping> swept_settings(int max_substeps) {
  std::vector<soda::Stepping> s = {soda::Stepping{}};
  for (soda::Integrator in : soda::kIntegrators) {
    for (int k = 1; k <= std::min(max_substeps, swept_max_substeps(in)); k *= 2) {
      s.push_back({soda::PhysicsMode::Continuous, in, k});
    }
  }
  return s;
}

double kendall_tau(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("kendall_tau: samples of different lengths");
  long long concordant = 0, discordant = 0, ties_a = 0, ties_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      const double da = a[i] - a[j];
      const double db = b[i] - b[j];
      if (da == 0.0 && db == 0.0) continue;
      if (da == 0.0) ++ties_a;
      else if (db == 0.0) ++ties_b;
      else if ((da > 0.0) == (db > 0.0)) ++concordant;
      else ++discordant;
    }
  }
  const double n1 = static_cast<double>(concordant + discordant + ties_a);
  const double n2 = static_cast<double>(concordant + discordant + ties_b);
  if (n1 == 0.0 || n2 == 0.0) return 0.0;
  return static_cast<double>(concordant - discordant) / std::sqrt(n1 * n2);
}

AccuracyReport run_accuracy_bench(const AccuracyOptions& options) {
  AccuracyOptions o = options;
  if (o.quick) {
    o.walkers = std::min(o.walkers, 20);
    o.walker_frames = std::min<long long>(o.walker_frames, 200);
    o.classic_frames = std::min<long long>(o.classic_frames, 300);
    o.settle_frames = std::min<long long>(o.settle_frames, 50);
    o.max_substeps = std::min(o.max_substeps, 8);
    o.reference_substeps = std::min(o.reference_substeps, 32);
  }
  const std::vector<soda::Stepping> settings = swept_settings(o.max_substeps);
  AccuracyReport report;
  analytic_section(o, settings, report);
  classic_section(o, settings, report);
  walkers_section(o, settings, report);
  return report;
}

} // namespace sodaevo::bench
