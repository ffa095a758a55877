#include "extreme_creatures.hpp"

#include <algorithm>
#include <cmath>

#include "core/model.hpp"
#include "core/step_failure.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/evaluators/parallel_for.hpp"

namespace sodaevo::bench {

namespace {

/// `extreme` with probability p, else uniform in [lo, hi].
double edge_or_uniform(Rng& rng, double p, double extreme, double lo, double hi) {
  return rng.chance(p) ? extreme : rng.uniform(lo, hi);
}

double rest_length(Rng& rng, const soda::NodeDef& a, const soda::NodeDef& b) {
  const double d = std::hypot(b.x - a.x, b.y - a.y);
  const double u = rng.uniform();
  if (u < 0.10) return 0.0;
  if (u < 0.20) return -rng.uniform(0.0, 300.0);
  if (u < 0.21) return 1.7e308; // legal (finite) and absurd: overflows the impulse
  if (u < 0.30) return d * rng.uniform(3.0, 20.0);
  return d * rng.uniform(0.5, 1.5);
}

} // namespace

soda::ModelDef extreme_creature(Rng& rng) {
  soda::ModelDef c;
  c.width = rng.chance(0.2) ? rng.between(1, 40) : rng.between(100, 2000);
  c.height = rng.chance(0.2) ? rng.between(1, 40) : rng.between(100, 1000);
  c.environment.springyness = edge_or_uniform(rng, 0.5, soda::kSpringynessRange.max, 0.0, 0.5);
  c.environment.gravity = edge_or_uniform(rng, 0.4, soda::kGravityRange.max, 0.0, 4.0);
  const double fu = rng.uniform();
  c.environment.friction = fu < 0.3 ? 0.0 : fu < 0.35 ? 1.0 : rng.uniform(0.0, 1.0);
  c.collisions.surface_friction = edge_or_uniform(rng, 0.3, rng.chance(0.5) ? 0.0 : 1.0, 0.0, 1.0);
  c.collisions.surface_reflection = edge_or_uniform(rng, 0.3, rng.chance(0.5) ? 0.0 : -1.0, -1.0, 0.0);
  c.wave.amplitude = edge_or_uniform(rng, 0.3, 1.0, 0.0, 1.0);
  c.wave.phase = rng.uniform();
  c.wave.speed = rng.chance(0.2) ? rng.uniform(-3.0, 3.0) : rng.uniform(-0.1, 0.1);
  c.settings.gravity_direction = static_cast<soda::GravityDirection>(rng.between(-1, 1));
  c.settings.wave_direction = static_cast<soda::WaveDirection>(rng.between(-1, 1));
  c.settings.autoreverse = rng.chance(0.5);

  const int masses = rng.between(2, 14);
  const int fixed = rng.chance(0.15) ? rng.between(1, 3) : 0;
  for (int i = 0; i < masses + fixed; ++i) {
    soda::NodeDef n;
    n.id = (i < masses ? "m" : "n") + std::to_string(i);
    n.fixed = i >= masses;
    if (i > 0 && rng.chance(0.2)) { // coincident with an earlier node
      const soda::NodeDef& other = c.nodes[rng.below(c.nodes.size())];
      n.x = other.x;
      n.y = other.y;
      if (rng.chance(0.5)) n.y += 1e-9; // nearly coincident: a link of length 1e-9 along y
    } else {
      n.x = rng.uniform(-200.0, c.width + 200.0); // sometimes outside the container
      n.y = rng.uniform(-200.0, c.height + 200.0);
    }
    if (!n.fixed && rng.chance(0.3)) {
      n.vx = rng.uniform(-60.0, 60.0); // above the 20 px/frame limit
      n.vy = rng.uniform(-60.0, 60.0);
    }
    c.nodes.push_back(n);
  }
  const int nodes = masses + fixed;
  auto add_link = [&](int a, int b) {
    if (a == b) return;
    soda::LinkDef l;
    const double kind = rng.uniform();
    l.kind = kind < 0.5 ? soda::LinkKind::Muscle : soda::LinkKind::Spring;
    if (kind > 0.97 && fixed > 0) l.kind = soda::LinkKind::FixedBar;
    l.a = a;
    l.b = b;
    if (l.kind != soda::LinkKind::FixedBar) l.rest_length = rest_length(rng, c.nodes[a], c.nodes[b]);
    if (l.kind == soda::LinkKind::Muscle) {
      l.amplitude = edge_or_uniform(rng, 0.3, 1.0, 0.0, 1.0);
      l.phase = rng.uniform();
    }
    c.links.push_back(l);
  };
  for (int i = 1; i < masses; ++i) add_link(i, rng.between(0, i - 1)); // connected
  const int extra = rng.between(0, 3 * nodes);
  for (int k = 0; k < extra; ++k) add_link(rng.between(0, nodes - 1), rng.between(0, nodes - 1));
  if (rng.chance(0.25)) { // a hub: many links on one mass
    const int hub = rng.between(0, masses - 1);
    const int spokes = rng.between(20, 80);
    for (int k = 0; k < spokes; ++k) add_link(hub, rng.between(0, nodes - 1));
  }
  if (rng.chance(0.25) && !c.links.empty()) { // links listed twice
    const int twice = rng.between(1, static_cast<int>(c.links.size()));
    for (int k = 0; k < twice; ++k) c.links.push_back(c.links[rng.below(c.links.size())]);
  }
  // Fixed bars between fixed nodes and masses are legal too, but a bar needs two
  // distinct ends, which add_link already ensures.
  return c;
}

namespace {

bool all_finite(const soda::Model& m, const soda::State& s) {
  if (!std::isfinite(s.wave_phase)) return false;
  for (int p = 0; p < m.point_count; ++p) {
    if (!std::isfinite(s.x[p]) || !std::isfinite(s.y[p]) || !std::isfinite(s.vx[p]) || !std::isfinite(s.vy[p])) {
      return false;
    }
  }
  return true;
}

struct CreatureResult {
  enum class Kind { Healthy, NonFinite, Energy, Escape } kind = Kind::Healthy;
  std::string what;
  long long frames = 0;
};

CreatureResult stress_one(const soda::ModelDef& def, const soda::Stepping& stepping, long long frames, bool energy,
                          bool check_fitness) {
  CreatureResult r;
  soda::Model model;
  try {
    model = soda::build_model(def);
  } catch (const std::exception& e) {
    return {CreatureResult::Kind::Escape, std::string("build_model rejected a legal creature: ") + e.what(), 0};
  }
  soda::State state = soda::make_state(model);
  soda::FrameStepper stepper(model, stepping, frames);
  soda::DivergenceMonitor monitor(model, state, {}, energy);
  for (long long f = 0; f < frames; ++f) {
    try {
      stepper.step(state);
    } catch (const soda::StepFailure& failure) { // an implicit solve failed: diverged, state kept finite
      r.kind = CreatureResult::Kind::NonFinite;
      r.what = "frame " + std::to_string(failure.frame) + ": " + failure.reason;
      break;
    }
    ++r.frames;
    const bool healthy = monitor.check(state);
    if (healthy && !all_finite(model, state)) {
      return {CreatureResult::Kind::Escape, "non-finite state not flagged at frame " + std::to_string(state.frame),
              r.frames};
    }
    if (!healthy) {
      const soda::Divergence& d = monitor.result();
      const bool state_went_bad = d.reason.rfind("non-finite", 0) == 0 && d.reason != "non-finite energy";
      r.kind = state_went_bad ? CreatureResult::Kind::NonFinite : CreatureResult::Kind::Energy;
      r.what = "frame " + std::to_string(d.frame) + ": " + d.reason;
      break;
    }
  }
  if (check_fitness) {
    // The GA's path: an Ok evaluation must carry finite numbers.
    FitnessConfig fc;
    fc.frames = frames;
    fc.settle_frames = 0;
    const Evaluation e = WalkProblem(fc, {}, {}).rollout_with(def, stepping);
    if (e.ok() && (!std::isfinite(e.distance) || !std::isfinite(e.fitness))) {
      return {CreatureResult::Kind::Escape, "fitness Ok with a non-finite distance", r.frames};
    }
    if (!e.ok() && e.status != EvaluationStatus::Diverged) {
      return {CreatureResult::Kind::Escape, "fitness rejected a legal creature: " + e.reason, r.frames};
    }
  }
  return r;
}

} // namespace

std::vector<StressCounts> run_stress(const StressOptions& o) {
  const std::size_t n_step = o.steppings.size();
  std::vector<CreatureResult> results(static_cast<std::size_t>(o.creatures) * n_step);
  parallel_for_index(static_cast<std::size_t>(o.creatures), o.threads, [&](std::size_t i) {
    Rng rng = Rng::stream(o.seed, i, 0, 0x57e55);
    const soda::ModelDef def = extreme_creature(rng);
    for (std::size_t k = 0; k < n_step; ++k) {
      results[i * n_step + k] = stress_one(def, o.steppings[k], o.frames, o.energy_check, k == 0);
    }
  });
  std::vector<StressCounts> counts(n_step);
  for (std::size_t k = 0; k < n_step; ++k) counts[k].stepping = soda::stepping_label(o.steppings[k]);
  for (std::size_t i = 0; i < results.size(); ++i) {
    StressCounts& c = counts[i % n_step];
    const CreatureResult& r = results[i];
    ++c.tried;
    c.frames_stepped += r.frames;
    switch (r.kind) {
      case CreatureResult::Kind::Healthy: break;
      case CreatureResult::Kind::NonFinite: ++c.diverged_non_finite; break;
      case CreatureResult::Kind::Energy: ++c.diverged_energy; break;
      case CreatureResult::Kind::Escape:
        ++c.escaped;
        if (c.first_escape.empty()) c.first_escape = "creature " + std::to_string(i / n_step) + ": " + r.what;
        break;
    }
    if (c.example_diverged.empty() && !r.what.empty() && r.kind != CreatureResult::Kind::Escape) {
      c.example_diverged = "creature " + std::to_string(i / n_step) + ", " + r.what;
    }
  }
  return counts;
}

} // namespace sodaevo::bench
