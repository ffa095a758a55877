#include "accuracy_bench.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "bench/analytic_scenes.hpp"
#include "bench/median.hpp"
#include "bench/replica_runs.hpp"
#include "core/model.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/algorithms/variation.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::bench {

namespace {

/// A walker "moves" when its reference centroid walks at least this fast, px/frame.
constexpr double kMoverSpeed = 0.1;
/// A creature "walks" when its reference distance exceeds this, px.
constexpr double kWalkingDistance = 50.0;

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double d = std::fabs(a[i] - b[i]);
    worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(worst, d);
  }
  return worst;
}

/// The scale relative errors are taken against: the reference distance, at least 1 px.
double scale_of(double reference) { return std::max(std::fabs(reference), 1.0); }

double relative_error(double value, double reference) {
  const double e = std::fabs(value - reference) / scale_of(reference);
  return std::isnan(e) ? std::numeric_limits<double>::infinity() : e;
}

void say(const AccuracyOptions& o, const std::string& line) {
  if (o.progress) o.progress(line);
}

soda::Stepping reference_of(const AccuracyOptions& o, int divisor = 1) {
  return {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, o.reference_substeps / divisor};
}

RunConfig creature_config(const AccuracyOptions& o) {
  RunConfig c;
  c.world.evolve = world_parameter_names(); // keep each creature's own world
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

/// Classics or champions: every setting's expected distance against the reference's.
void creature_section(const AccuracyOptions& o, const std::string& section,
                      const std::vector<std::pair<std::string, std::string>>& creatures,
                      const std::vector<soda::Stepping>& settings, AccuracyReport& out) {
  const RunConfig config = creature_config(o);
  ReplicaPlan plan;
  plan.replicas = o.replicas;
  plan.jitter = o.jitter;
  const long long settle = o.settle_frames, end = o.settle_frames + o.classic_frames;
  const long long early = std::min<long long>(100, end);
  plan.checkpoints = {early, settle, end};
  std::sort(plan.checkpoints.begin(), plan.checkpoints.end());
  plan.checkpoints.erase(std::unique(plan.checkpoints.begin(), plan.checkpoints.end()), plan.checkpoints.end());
  auto index_of = [&](long long f) {
    return static_cast<std::size_t>(std::find(plan.checkpoints.begin(), plan.checkpoints.end(), f) -
                                    plan.checkpoints.begin());
  };
  plan.from = index_of(settle);
  plan.to = index_of(end);
  plan.keep = index_of(early);
  for (const auto& [name, path] : creatures) {
    say(o, section + ": " + name + ", reference");
    const soda::ModelDef creature = creature_from_seed(soda::read_model_file(path).def, config);
    const soda::Model model = soda::build_model(walk_problem_of(config).prepare(creature));
    const ExpectedDistance ref = expected_distance(model, reference_of(o), plan);
    const ExpectedDistance half_ref = expected_distance(model, reference_of(o, 2), plan);
    const double scale = scale_of(ref.summary.mean);
    const DifferenceInterval half = difference_interval(half_ref, ref);
    const double half_width = ref.summary.n > 1 ? student_t_975(ref.summary.n - 1) * ref.standard_error : 0.0;
    out.references.push_back({section, name, ref.summary.mean, ref.standard_error, ref.summary.sd, half_width,
                              half.difference / scale, half.low / scale, half.high / scale});
    if (std::fabs(ref.summary.mean) > kWalkingDistance) {
      (section == "champion" ? out.walkers_among_champions : out.walkers_among_classics).push_back(name);
    }
    for (const soda::Stepping& st : settings) {
      say(o, section + ": " + name + ", " + soda::stepping_label(st));
      const ExpectedDistance e = expected_distance(model, st, plan);
      const DifferenceInterval d = difference_interval(e, ref);
      AccuracyRow row;
      row.section = section;
      row.scene = name;
      row.stepping = st;
      row.seconds_per_frame = e.seconds_per_frame;
      row.position_error = max_abs_difference(e.exact_positions, ref.exact_positions);
      row.distance = e.summary.mean;
      row.distance_se = e.standard_error;
      row.reference_distance = ref.summary.mean;
      row.reference_se = ref.standard_error;
      row.distance_error = relative_error(e.summary.mean, ref.summary.mean);
      row.error_low = d.low / scale;
      row.error_high = d.high / scale;
      row.exact_distance = e.exact;
      row.exact_error = relative_error(e.exact, ref.exact);
      row.diverged = e.diverged;
      out.rows.push_back(row);
    }
  }
}

/// Per walker, the expected distance of one setting (the GA's rank of a creature
/// with a diverged replica: the worst) and replica 0's.
struct WalkerDistances {
  std::vector<double> expected, exact, standard_error;
  double seconds = 0.0;
  int diverged = 0;
};

std::vector<soda::Model> random_walkers(const AccuracyOptions& o) {
  RunConfig config;
  config.fitness.frames = o.walker_frames;
  config.fitness.settle_frames = o.settle_frames;
  std::vector<soda::Model> models;
  for (std::uint64_t i = 0; static_cast<int>(models.size()) < o.walkers && i < 100ull * o.walkers; ++i) {
    Rng rng = Rng::stream(o.seed, i, 0, 0xacc);
    try {
      models.push_back(soda::build_model(walk_problem_of(config).prepare(random_creature(config, rng))));
    } catch (const std::exception&) {
      // e.g. too small to scale within gravity's range: draw another
    }
  }
  return models;
}

void walkers_section(const AccuracyOptions& o, const std::vector<soda::Stepping>& settings, AccuracyReport& out) {
  const std::vector<soda::Model> models = random_walkers(o);
  ReplicaPlan plan;
  plan.replicas = o.replicas;
  plan.jitter = o.jitter;
  plan.checkpoints = {o.settle_frames, o.settle_frames + o.walker_frames};
  plan.from = 0;
  plan.to = 1;
  auto distances = [&](const soda::Stepping& st) {
    WalkerDistances d;
    for (const soda::Model& m : models) {
      const ExpectedDistance e = expected_distance(m, st, plan);
      d.seconds += e.seconds_per_frame;
      const double worst = -std::numeric_limits<double>::max();
      if (e.diverged > 0) ++d.diverged;
      d.expected.push_back(e.diverged > 0 ? worst : e.summary.mean);
      d.exact.push_back(std::isnan(e.exact) ? worst : e.exact);
      d.standard_error.push_back(e.standard_error);
    }
    d.seconds /= static_cast<double>(std::max<std::size_t>(1, models.size()));
    return d;
  };
  out.walkers = static_cast<int>(models.size());
  say(o, "walkers: " + std::to_string(models.size()) + " random creatures, reference");
  const WalkerDistances ref = distances(reference_of(o));
  const WalkerDistances half_ref = distances(reference_of(o, 2));
  // The movers: creatures whose reference walks at least kMoverSpeed. Among the
  // others the ranking is a ranking of jitter.
  std::vector<std::size_t> movers;
  for (std::size_t i = 0; i < ref.expected.size(); ++i) {
    const double v = std::fabs(ref.expected[i]);
    if (v >= kMoverSpeed * static_cast<double>(o.walker_frames) && v < 1e300) movers.push_back(i); // not diverged
  }
  auto subset = [&](const std::vector<double>& v) {
    std::vector<double> values;
    for (std::size_t i : movers) values.push_back(v[i]);
    return values;
  };
  out.walkers_movers = static_cast<int>(movers.size());
  out.walkers_noise_floor_tau = kendall_tau(half_ref.expected, ref.expected);
  out.walkers_noise_floor_tau_movers = kendall_tau(subset(half_ref.expected), subset(ref.expected));
  out.walkers_noise_floor_tau_exact_movers = kendall_tau(subset(half_ref.exact), subset(ref.exact));
  const std::vector<double> mover_means = subset(ref.expected), mover_errors = subset(ref.standard_error);
  auto scaled = [&](double factor) {
    std::vector<double> e = mover_errors;
    for (double& v : e) v *= factor;
    return e;
  };
  out.walkers_predicted_tau_movers = predicted_tau(mover_means, mover_errors);
  out.walkers_predicted_tau_movers_4r = predicted_tau(mover_means, scaled(0.5));
  out.walkers_predicted_tau_movers_16r = predicted_tau(mover_means, scaled(0.25));
  std::vector<double> relative_se;
  for (std::size_t k = 0; k < movers.size(); ++k) relative_se.push_back(mover_errors[k] / scale_of(mover_means[k]));
  out.walkers_median_relative_se = median(relative_se);
  for (const soda::Stepping& st : settings) {
    say(o, "walkers: " + soda::stepping_label(st));
    const WalkerDistances d = distances(st);
    AccuracyRow row;
    row.section = "walkers";
    row.scene = std::to_string(models.size()) + " random walkers";
    row.stepping = st;
    row.diverged = d.diverged;
    row.seconds_per_frame = d.seconds;
    row.kendall_tau = kendall_tau(d.expected, ref.expected);
    row.kendall_tau_movers = kendall_tau(subset(d.expected), subset(ref.expected));
    row.kendall_tau_exact_movers = kendall_tau(subset(d.exact), subset(ref.exact));
    std::vector<double> errors, exact_errors;
    for (std::size_t i : movers) {
      errors.push_back(relative_error(d.expected[i], ref.expected[i]));
      exact_errors.push_back(relative_error(d.exact[i], ref.exact[i]));
    }
    row.distance_error = median(errors);
    row.exact_error = median(exact_errors);
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

double predicted_tau(const std::vector<double>& means, const std::vector<double>& errors) {
  if (means.size() != errors.size()) throw std::invalid_argument("predicted_tau: samples of different lengths");
  double sum = 0.0;
  long long pairs = 0;
  for (std::size_t i = 0; i < means.size(); ++i) {
    for (std::size_t j = i + 1; j < means.size(); ++j) {
      const double s = std::sqrt(errors[i] * errors[i] + errors[j] * errors[j]);
      const double gap = std::fabs(means[i] - means[j]);
      // 2 Phi(g / s) - 1 = erf(g / (s sqrt 2)): how likely one estimate orders the pair right.
      const double agree = s > 0.0 ? std::erf(gap / (s * std::sqrt(2.0))) : (gap > 0.0 ? 1.0 : 0.0);
      sum += agree * agree;
      ++pairs;
    }
  }
  return pairs > 0 ? sum / static_cast<double>(pairs) : 0.0;
}

AccuracyReport run_accuracy_bench(const AccuracyOptions& options) {
  AccuracyOptions o = options;
  if (o.quick) {
    o.walkers = std::min(o.walkers, 20);
    o.walker_frames = std::min<long long>(o.walker_frames, 200);
    o.classic_frames = std::min<long long>(o.classic_frames, 300);
    o.settle_frames = std::min<long long>(o.settle_frames, 50);
    o.max_substeps = std::min(o.max_substeps, 8);
    o.walker_max_substeps = std::min(o.walker_max_substeps, 4);
    o.reference_substeps = std::min(o.reference_substeps, 32);
    o.replicas = std::min(o.replicas, 3);
  }
  if (o.replicas < 2) throw std::invalid_argument("bench accuracy: at least 2 replicas (a standard error needs two)");
  AccuracyReport report;
  report.replicas = o.replicas;
  report.reference = reference_of(o);
  report.creature_frames = o.classic_frames;
  report.settle_frames = o.settle_frames;
  const std::vector<soda::Stepping> settings = swept_settings(o.max_substeps);
  analytic_section(o, settings, report);
  creature_section(o, "classic", o.classics, settings, report);
  creature_section(o, "champion", o.champions, settings, report);
  walkers_section(o, swept_settings(o.walker_max_substeps), report);
  return report;
}

} // namespace sodaevo::bench
