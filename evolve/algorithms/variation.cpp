#include "variation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/input_error.hpp"
#include "core/sine.hpp"
#include "evolve/problems/creature_graph.hpp"
#include "evolve/problems/creature_limits.hpp"

namespace sodaevo {

namespace {

constexpr double kMinRestLength = 1.0; // px; keeps mutated links from collapsing

/// sqrt(dx^2 + dy^2): rounded the same everywhere, unlike the C library's hypot
/// (evolve/algorithms/rng.hpp says why that matters).
double distance(const soda::NodeDef& a, const soda::NodeDef& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  return std::sqrt(dx * dx + dy * dy);
}

soda::LinkDef new_link(const soda::ModelDef& c, int a, int b, bool muscle, Rng& rng) {
  soda::LinkDef l;
  l.kind = muscle ? soda::LinkKind::Muscle : soda::LinkKind::Spring;
  l.a = a;
  l.b = b;
  l.rest_length = std::max(kMinRestLength, distance(c.nodes[a], c.nodes[b]));
  if (muscle) {
    l.amplitude = rng.uniform(0.2, 1.0);
    l.phase = rng.uniform();
  }
  return l;
}

void apply_world(soda::ModelDef& c, const WorldConfig& w) {
  c.environment = {w.gravity, w.friction, w.springyness};
  c.collisions = {w.surface_friction, w.surface_reflection};
  c.settings.gravity_direction = w.gravity_direction;
  c.settings.wave_direction = soda::WaveDirection::Forward;
  c.settings.autoreverse = false;
}

std::vector<int> indices_of_kind(const soda::ModelDef& c, soda::LinkKind kind) {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(c.links.size()); ++i) {
    if (c.links[i].kind == kind) out.push_back(i);
  }
  return out;
}

template <class T>
const T& pick(const std::vector<T>& v, Rng& rng) {
  return v[rng.below(v.size())];
}

void relabel(soda::ModelDef& c) {
  for (std::size_t i = 0; i < c.nodes.size(); ++i) c.nodes[i].id = "m" + std::to_string(i);
}

/// Joins separate components with a spring between their nearest masses.
void join_components(soda::ModelDef& c) {
  for (;;) {
    int count = 0;
    const std::vector<int> comp = connected_components(c, &count);
    if (count <= 1) return;
    int best_a = -1, best_b = -1;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < static_cast<int>(c.nodes.size()); ++i) {
      if (comp[i] != 0) continue;
      for (int j = 0; j < static_cast<int>(c.nodes.size()); ++j) {
        if (comp[j] == 0) continue;
        const double d = distance(c.nodes[i], c.nodes[j]);
        if (d < best) {
          best = d;
          best_a = i;
          best_b = j;
        }
      }
    }
    soda::LinkDef l;
    l.a = best_a;
    l.b = best_b;
    l.rest_length = std::max(kMinRestLength, best);
    c.links.push_back(l);
  }
}

// --- the mutation operators: each returns true if it changed the creature ---

bool mutate_muscle_phase(soda::ModelDef& c, const MutationConfig& m, Rng& rng) {
  const auto muscles = indices_of_kind(c, soda::LinkKind::Muscle);
  if (muscles.empty()) return false;
  soda::LinkDef& l = c.links[pick(muscles, rng)];
  l.phase = soda::wrap_phase(l.phase + m.muscle_phase_sigma * rng.normal());
  return true;
}

bool mutate_muscle_amplitude(soda::ModelDef& c, const MutationConfig& m, Rng& rng) {
  const auto muscles = indices_of_kind(c, soda::LinkKind::Muscle);
  if (muscles.empty()) return false;
  soda::LinkDef& l = c.links[pick(muscles, rng)];
  l.amplitude = std::clamp(l.amplitude + m.muscle_amplitude_sigma * rng.normal(), 0.0, 1.0);
  return true;
}

bool mutate_rest_length(soda::ModelDef& c, const MutationConfig& m, Rng& rng) {
  if (c.links.empty()) return false;
  soda::LinkDef& l = c.links[rng.below(c.links.size())];
  l.rest_length = std::max(kMinRestLength, l.rest_length * (1.0 + m.rest_length_sigma * rng.normal()));
  return true;
}

bool mutate_wave(soda::ModelDef& c, const MutationConfig& m, Rng& rng) {
  c.wave.speed = std::clamp(c.wave.speed + m.wave_speed_sigma * rng.normal(), -soda::kWaveMaxUiSpeed,
                            soda::kWaveMaxUiSpeed);
  c.wave.amplitude = std::clamp(c.wave.amplitude + m.wave_amplitude_sigma * rng.normal(), 0.0, 1.0);
  return true;
}

bool mutate_move_mass(soda::ModelDef& c, const MutationConfig& m, Rng& rng) {
  soda::NodeDef& n = c.nodes[rng.below(c.nodes.size())];
  n.x += m.move_mass_sigma * rng.normal();
  n.y = std::max(0.0, n.y + m.move_mass_sigma * rng.normal());
  return true;
}

bool mutate_add_link(soda::ModelDef& c, const GeneticSettings& cfg, Rng& rng) {
  if (static_cast<int>(c.links.size()) >= cfg.limits.max_links) return false;
  std::vector<std::pair<int, int>> free_pairs;
  const int n = static_cast<int>(c.nodes.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (!are_linked(c, a, b)) free_pairs.emplace_back(a, b);
    }
  }
  if (free_pairs.empty()) return false;
  const auto [a, b] = pick(free_pairs, rng);
  c.links.push_back(new_link(c, a, b, rng.chance(cfg.population.random.muscle_fraction), rng));
  return true;
}

bool mutate_remove_link(soda::ModelDef& c, Rng& rng) {
  if (c.links.size() <= 1) return false;
  // Try links in a random order; remove the first whose loss keeps the creature whole.
  std::vector<int> order(c.links.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  for (std::size_t i = order.size() - 1; i > 0; --i) std::swap(order[i], order[rng.below(i + 1)]);
  for (int i : order) {
    soda::ModelDef trial = c;
    trial.links.erase(trial.links.begin() + i);
    if (is_connected(trial)) {
      c = std::move(trial);
      return true;
    }
  }
  return false;
}

bool mutate_toggle_muscle(soda::ModelDef& c, Rng& rng) {
  if (c.links.empty()) return false;
  soda::LinkDef& l = c.links[rng.below(c.links.size())];
  if (l.kind == soda::LinkKind::Muscle) {
    l.kind = soda::LinkKind::Spring;
    l.amplitude = 0.0;
    l.phase = 0.0;
  } else {
    l.kind = soda::LinkKind::Muscle;
    l.amplitude = rng.uniform(0.2, 1.0);
    l.phase = rng.uniform();
  }
  return true;
}

bool mutate_add_mass(soda::ModelDef& c, const GeneticSettings& cfg, Rng& rng) {
  const int n = static_cast<int>(c.nodes.size());
  if (n >= cfg.limits.max_masses || n < 2 || static_cast<int>(c.links.size()) + 2 > cfg.limits.max_links) return false;
  const soda::NodeDef& p = c.nodes[rng.below(n)];
  const double angle = rng.uniform(0.0, 6.283185307179586);
  const double radius = rng.uniform(0.3, 1.0) * std::max(20.0, cfg.population.random.size / 3.0);
  soda::NodeDef added;
  // The engine's own sine (the C library's differs between machines): cos a = sin(a + pi/2).
  added.x = p.x + radius * soda::sine(angle + 1.5707963267948966);
  added.y = std::max(0.0, p.y + radius * soda::sine(angle));
  // Join it to its two nearest masses (three when allowed and available).
  std::vector<std::pair<double, int>> by_distance;
  for (int i = 0; i < n; ++i) by_distance.emplace_back(distance(added, c.nodes[i]), i);
  std::sort(by_distance.begin(), by_distance.end());
  c.nodes.push_back(added);
  const int links = (n >= 3 && static_cast<int>(c.links.size()) + 3 <= cfg.limits.max_links && rng.chance(0.5)) ? 3 : 2;
  for (int k = 0; k < links; ++k) {
    c.links.push_back(new_link(c, n, by_distance[k].second, rng.chance(cfg.population.random.muscle_fraction), rng));
  }
  return true;
}

void remove_node(soda::ModelDef& c, int victim) {
  c.nodes.erase(c.nodes.begin() + victim);
  std::vector<soda::LinkDef> kept;
  for (soda::LinkDef l : c.links) {
    if (l.a == victim || l.b == victim) continue;
    if (l.a > victim) --l.a;
    if (l.b > victim) --l.b;
    kept.push_back(l);
  }
  c.links = std::move(kept);
}

bool mutate_remove_mass(soda::ModelDef& c, const GeneticSettings& cfg, Rng& rng) {
  const int n = static_cast<int>(c.nodes.size());
  if (n <= cfg.limits.min_masses) return false;
  const int start = static_cast<int>(rng.below(n));
  for (int k = 0; k < n; ++k) {
    soda::ModelDef trial = c;
    remove_node(trial, (start + k) % n);
    if (!trial.links.empty() && is_connected(trial)) {
      c = std::move(trial);
      return true;
    }
  }
  return false;
}

bool mutate_world(soda::ModelDef& c, const GeneticSettings& cfg, Rng& rng) {
  if (cfg.world.evolve.empty()) return false;
  const std::string& name = pick(cfg.world.evolve, rng);
  auto perturb = [&](double& v, soda::Range r) {
    v = std::clamp(v + cfg.mutation.world_sigma * (r.max - r.min) * rng.normal(), r.min, r.max);
  };
  if (name == "gravity") perturb(c.environment.gravity, soda::kGravityRange);
  else if (name == "friction") perturb(c.environment.friction, soda::kFrictionRange);
  else if (name == "springyness") perturb(c.environment.springyness, soda::kSpringynessRange);
  else if (name == "surface_friction") perturb(c.collisions.surface_friction, soda::kSurfaceFrictionRange);
  else if (name == "surface_reflection") perturb(c.collisions.surface_reflection, soda::kSurfaceReflectionRange);
  else return false;
  return true;
}

} // namespace

soda::ModelDef random_creature(const GeneticSettings& cfg, Rng& rng) {
  const RandomCreatureConfig& r = cfg.population.random;
  soda::ModelDef c;
  apply_world(c, cfg.world);
  c.wave = {rng.uniform(0.3, 1.0), 0.0, rng.uniform(0.005, 0.04)};
  const int n = rng.between(r.masses_min, r.masses_max);
  for (int i = 0; i < n; ++i) {
    soda::NodeDef m;
    m.x = rng.uniform(0.0, r.size);
    m.y = rng.uniform(0.0, r.size);
    c.nodes.push_back(m);
  }
  for (int i = 1; i < n && static_cast<int>(c.links.size()) < cfg.limits.max_links; ++i) {
    // Drawn in this order, spelled out: as arguments of one call their order was
    // the compiler's (GCC right to left, clang left to right: the WebAssembly
    // build drew other creatures). This is the order every run so far drew them in.
    const bool muscle = rng.chance(r.muscle_fraction);
    const int to = static_cast<int>(rng.below(i));
    c.links.push_back(new_link(c, i, to, muscle, rng));
  }
  const int extra = static_cast<int>(std::lround(r.extra_links_per_mass * n));
  for (int k = 0; k < extra; ++k) {
    const int a = static_cast<int>(rng.below(n));
    const int b = static_cast<int>(rng.below(n));
    if (a == b || are_linked(c, a, b) || static_cast<int>(c.links.size()) >= cfg.limits.max_links) continue;
    c.links.push_back(new_link(c, a, b, rng.chance(r.muscle_fraction), rng));
  }
  relabel(c);
  return soda::canonical_form(c);
}

void mutate(soda::ModelDef& c, const GeneticSettings& cfg, Rng& rng) {
  const MutationConfig& m = cfg.mutation;
  bool changed = false;
  if (rng.chance(m.muscle_phase_rate)) changed |= mutate_muscle_phase(c, m, rng);
  if (rng.chance(m.muscle_amplitude_rate)) changed |= mutate_muscle_amplitude(c, m, rng);
  if (rng.chance(m.rest_length_rate)) changed |= mutate_rest_length(c, m, rng);
  if (rng.chance(m.wave_rate)) changed |= mutate_wave(c, m, rng);
  if (rng.chance(m.move_mass_rate)) changed |= mutate_move_mass(c, m, rng);
  if (rng.chance(m.add_link_rate)) changed |= mutate_add_link(c, cfg, rng);
  if (rng.chance(m.remove_link_rate)) changed |= mutate_remove_link(c, rng);
  if (rng.chance(m.toggle_muscle_rate)) changed |= mutate_toggle_muscle(c, rng);
  if (rng.chance(m.add_mass_rate)) changed |= mutate_add_mass(c, cfg, rng);
  if (rng.chance(m.remove_mass_rate)) changed |= mutate_remove_mass(c, cfg, rng);
  if (rng.chance(m.world_rate)) changed |= mutate_world(c, cfg, rng);
  // A child equal to its parent would waste an evaluation.
  if (!changed && !mutate_muscle_phase(c, m, rng)) mutate_rest_length(c, m, rng);
  relabel(c);
  c = soda::canonical_form(c);
}

soda::ModelDef crossover(const soda::ModelDef& a, const soda::ModelDef& b, const GeneticSettings& cfg, Rng& rng) {
  const int na = static_cast<int>(a.nodes.size()), nb = static_cast<int>(b.nodes.size());
  if (na < 2 || nb < 2) return a;
  const int k = rng.between(1, std::min(na, nb) - 1);
  soda::ModelDef child = a;
  child.nodes.assign(a.nodes.begin(), a.nodes.begin() + k);
  child.nodes.insert(child.nodes.end(), b.nodes.begin() + k, b.nodes.end());
  child.links.clear();
  for (const soda::LinkDef& l : a.links) {
    if (l.a < k && l.b < k) child.links.push_back(l);
  }
  for (const soda::LinkDef& l : b.links) {
    if ((l.a >= k || l.b >= k) && !are_linked(child, l.a, l.b)) child.links.push_back(l);
  }
  join_components(child);
  relabel(child);
  child = soda::canonical_form(child);
  if (check_creature(child, cfg.limits)) return a;
  return child;
}

soda::ModelDef creature_from_seed(const soda::ModelDef& seed, const GeneticSettings& cfg) {
  soda::ModelDef c = seed;
  for (int i = static_cast<int>(c.nodes.size()) - 1; i >= 0; --i) {
    if (c.nodes[i].fixed) remove_node(c, i);
  }
  std::erase_if(c.links, [](const soda::LinkDef& l) { return l.kind == soda::LinkKind::FixedBar; });
  int count = 0;
  const std::vector<int> comp = connected_components(c, &count);
  if (count > 1) {
    std::vector<int> sizes(count, 0);
    for (int x : comp) ++sizes[x];
    const int keep = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
    for (int i = static_cast<int>(c.nodes.size()) - 1; i >= 0; --i) {
      if (comp[i] != keep) remove_node(c, i);
    }
  }
  relabel(c);
  // Genomes always run the wave forward; a reverse wave becomes a negated speed,
  // which advances the phase by exactly the same numbers (phase + s*(-1) equals
  // phase + (-s)*1 in every bit), and a manual wave a speed of zero.
  if (c.settings.wave_direction == soda::WaveDirection::Reverse) c.wave.speed = -c.wave.speed;
  if (c.settings.wave_direction == soda::WaveDirection::Manual) c.wave.speed = 0.0;
  c.settings.wave_direction = soda::WaveDirection::Forward;
  c.settings.autoreverse = false;
  c = soda::canonical_form(c);
  if (std::optional<std::string> why = check_creature(c, cfg.limits)) {
    throw soda::InputError("seed model cannot be evolved: it " + *why);
  }
  return c;
}

} // namespace sodaevo
