#include "model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "input_error.hpp"
#include "number_text.hpp"
#include "physics_rules.hpp"
#include "detail/bits.hpp"

namespace soda {

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError("model: " + where + ": " + what);
}

std::string node_name(const ModelDef& def, std::size_t i) {
  return "node " + std::to_string(i) + " ('" + def.nodes[i].id + "')";
}

void require_finite(double v, const std::string& where, const char* field) {
  if (!std::isfinite(v)) fail(where, std::string(field) + ": expected a finite number, got " + format_double_plain(v));
}

void require_range(double v, Range range, const std::string& where, const char* field) {
  require_finite(v, where, field);
  if (!range.contains(v)) {
    fail(where, std::string(field) + ": expected a value in [" + format_double_plain(range.min) + ", " +
                    format_double_plain(range.max) + "], got " + format_double_plain(v));
  }
}

void require_phase(double v, const std::string& where, const char* field) {
  require_finite(v, where, field);
  if (!(v >= 0.0 && v < 1.0)) {
    fail(where, std::string(field) + ": expected a phase in [0, 1), got " + format_double_plain(v));
  }
}

void validate_world(const ModelDef& def) {
  if (def.width < 1 || def.height < 1) {
    fail("container", "expected width and height >= 1, got " + std::to_string(def.width) + "x" +
                          std::to_string(def.height));
  }
  require_range(def.environment.gravity, kGravityRange, "environment", "gravity");
  require_range(def.environment.friction, kFrictionRange, "environment", "friction");
  require_range(def.environment.springyness, kSpringynessRange, "environment", "springyness");
  require_range(def.collisions.surface_friction, kSurfaceFrictionRange, "collisions", "surface_friction");
  require_range(def.collisions.surface_reflection, kSurfaceReflectionRange, "collisions",
                "surface_reflection");
  require_range(def.wave.amplitude, kAmplitudeRange, "wave", "amplitude");
  require_phase(def.wave.phase, "wave", "phase");
  require_finite(def.wave.speed, "wave", "speed");
  auto gd = static_cast<int>(def.settings.gravity_direction);
  auto wd = static_cast<int>(def.settings.wave_direction);
  if (gd < -1 || gd > 1) fail("settings", "gravitydirection: expected down, up or off");
  if (wd < -1 || wd > 1) fail("settings", "wavedirection: expected forward, reverse or manual");
}

} // namespace

Model build_model(const ModelDef& def, BarEngine bar_engine) {
  validate_world(def);
  if (def.nodes.empty()) fail("nodes", "expected at least one node or mass, got an empty model");
  if (static_cast<long>(def.nodes.size()) > kMaxNodes) {
    fail("nodes", "expected at most " + std::to_string(kMaxNodes) + " nodes, got " + std::to_string(def.nodes.size()));
  }
  if (static_cast<long>(def.links.size()) > kMaxLinks) {
    fail("links", "expected at most " + std::to_string(kMaxLinks) + " links, got " + std::to_string(def.links.size()));
  }

  Model m;
  m.width = def.width;
  m.height = def.height;
  m.springyness = def.environment.springyness;
  m.friction = def.environment.friction;
  m.gravity = def.environment.gravity;
  m.gravity_direction = def.settings.gravity_direction;
  m.surface_friction = def.collisions.surface_friction;
  m.surface_reflection = def.collisions.surface_reflection;
  m.autoreverse = def.settings.autoreverse;
  m.wave_amplitude = def.wave.amplitude;
  m.wave_speed = def.wave.speed;
  m.wave_phase0 = def.wave.phase;
  m.wave_direction0 = def.settings.wave_direction;

  const auto node_count = def.nodes.size();
  m.point_of_node.assign(node_count, -1);
  for (bool fixed_pass : {false, true}) {
    for (std::size_t i = 0; i < node_count; ++i) {
      const NodeDef& node = def.nodes[i];
      if (node.fixed != fixed_pass) continue;
      const std::string where = node_name(def, i);
      require_finite(node.x, where, "x");
      require_finite(node.y, where, "y");
      require_finite(node.vx, where, "vx");
      require_finite(node.vy, where, "vy");
      m.point_of_node[i] = static_cast<int>(m.node_of_point.size());
      m.node_of_point.push_back(static_cast<int>(i));
      m.x0.push_back(node.x);
      m.y0.push_back(node.y);
      m.vx0.push_back(node.fixed ? 0.0 : node.vx);
      m.vy0.push_back(node.fixed ? 0.0 : node.vy);
    }
    if (!fixed_pass) m.mass_count = static_cast<int>(m.node_of_point.size());
  }
  m.point_count = static_cast<int>(m.node_of_point.size());

  for (std::size_t i = 0; i < def.links.size(); ++i) {
    const LinkDef& link = def.links[i];
    const std::string where = "link " + std::to_string(i);
    for (int end : {link.a, link.b}) {
      if (end < 0 || static_cast<std::size_t>(end) >= node_count) {
        fail(where, "expected a node index in [0, " + std::to_string(node_count) + "), got " + std::to_string(end));
      }
    }
    if (link.a == link.b) fail(where, "expected two different nodes, got a link from '" + def.nodes[link.a].id + "' to itself");
    const int a = m.point_of_node[link.a];
    const int b = m.point_of_node[link.b];
    if (link.kind == LinkKind::FixedBar) {
      m.bar_a.push_back(a);
      m.bar_b.push_back(b);
      continue;
    }
    require_finite(link.rest_length, where, "restlength");
    const bool muscle = link.kind == LinkKind::Muscle;
    if (muscle) {
      require_range(link.amplitude, kAmplitudeRange, where, "amplitude");
      require_phase(link.phase, where, "phase");
    }
    m.link_a.push_back(a);
    m.link_b.push_back(b);
    m.link_rest.push_back(link.rest_length);
    m.link_muscle.push_back(muscle ? 1 : 0);
    m.link_amplitude.push_back(muscle ? link.amplitude : 0.0);
    m.link_phase.push_back(muscle ? link.phase : 0.0);
  }
  m.fixed_bars = make_fixed_bars(m.bar_a, m.bar_b, m.x0.data(), m.y0.data(), bar_engine);
  set_constants(m);
  return m;
}

namespace {
/// The derived constants of a Model's fields (set_constants).
struct DerivedConstants {
  double gravity_step = 0.0;
  double air_keep = 1.0;
  std::vector<double> link_power;
};

DerivedConstants derived_constants(const Model& model) {
  DerivedConstants d;
  d.gravity_step = rules::gravity_step(model.gravity, model.gravity_direction);
  d.air_keep = rules::air_keep(model.friction);
  d.link_power.resize(model.link_muscle.size());
  for (std::size_t i = 0; i < model.link_muscle.size(); ++i) {
    d.link_power[i] = model.link_muscle[i] ? rules::muscle_power(model.wave_amplitude, model.link_amplitude[i]) : 0.0;
  }
  return d;
}
} // namespace

void set_constants(Model& model) {
  DerivedConstants d = derived_constants(model);
  model.gravity_step = d.gravity_step;
  model.air_keep = d.air_keep;
  model.link_power = std::move(d.link_power);
}

bool constants_current(const Model& model) {
  const DerivedConstants d = derived_constants(model);
  const auto same = [](double a, double b) { return bits_of(a) == bits_of(b); };
  return same(d.gravity_step, model.gravity_step) && same(d.air_keep, model.air_keep) &&
         std::equal(d.link_power.begin(), d.link_power.end(), model.link_power.begin(), model.link_power.end(), same);
}

State make_state(const Model& model) {
  State s;
  s.x = model.x0;
  s.y = model.y0;
  s.vx = model.vx0;
  s.vy = model.vy0;
  s.wave_phase = model.wave_phase0;
  s.wave_mode = model.wave_direction0;
  return s;
}

namespace {
bool fits(const State& s, int points) {
  const auto n = static_cast<std::size_t>(points);
  return s.x.size() == n && s.y.size() == n && s.vx.size() == n && s.vy.size() == n;
}
} // namespace

void require_state_size(const State& state, int points, const char* who) {
  if (fits(state, points)) return;
  throw std::invalid_argument(std::string(who) + ": the state does not fit the model: expected " +
                              std::to_string(points) + " points in x, y, vx and vy, got " +
                              std::to_string(state.x.size()) + ", " + std::to_string(state.y.size()) + ", " +
                              std::to_string(state.vx.size()) + " and " + std::to_string(state.vy.size()));
}

// Called before every run, also of one frame (FastStepper::step): nothing is
// allocated unless something is wrong, or the batch is large.
void require_batch_states(State* const* states, int count, const std::function<int(int)>& points_of,
                          const char* who) {
  const auto which = [&](int c) { return std::string(who) + ": states[" + std::to_string(c) + "]"; };
  const auto twice = [&](int first, int again) {
    throw std::invalid_argument(which(again) + " is the same State as states[" + std::to_string(first) +
                                "]: each creature needs its own");
  };
  for (int c = 0; c < count; ++c) {
    if (states[c] == nullptr) throw std::invalid_argument(which(c) + " is null");
    if (!fits(*states[c], points_of(c))) require_state_size(*states[c], points_of(c), which(c).c_str());
  }
  constexpr int kPairwiseUpTo = 32;
  if (count <= kPairwiseUpTo) {
    for (int c = 1; c < count; ++c) {
      for (int e = 0; e < c; ++e) {
        if (states[e] == states[c]) twice(e, c);
      }
    }
    return;
  }
  std::vector<std::pair<std::uintptr_t, int>> sorted; // integers: pointers of different objects do not order
  sorted.reserve(static_cast<std::size_t>(count));
  for (int c = 0; c < count; ++c) sorted.emplace_back(reinterpret_cast<std::uintptr_t>(states[c]), c);
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k].first == sorted[k - 1].first) twice(sorted[k - 1].second, sorted[k].second);
  }
}

ModelDef def_with_state(const ModelDef& def, const Model& model, const State& state) {
  ModelDef out = def;
  for (int p = 0; p < model.point_count; ++p) {
    NodeDef& node = out.nodes[static_cast<std::size_t>(model.node_of_point[p])];
    node.x = state.x[p];
    node.y = state.y[p];
    node.vx = state.vx[p];
    node.vy = state.vy[p];
    // The original's writer puts a mass lying on a bar 1e-4 off it (FixedBar.TWEAK).
    if (p < model.mass_count) tweak_for_writing(model.fixed_bars, state.bar_memory, p, node.x, node.y);
  }
  // A running wave can stand at exactly 1.0 (rules::wrap_moved_wave_phase); a file's
  // phase lies in [0, 1) and the original's reader wraps 1.0 to 0: written as read.
  out.wave.phase = state.wave_phase == 1.0 ? 0.0 : state.wave_phase;
  out.settings.wave_direction = state.wave_mode;
  return out;
}

Point2 mass_centroid(const Model& model, const State& state) {
  if (model.mass_count == 0) return {};
  double sx = 0.0, sy = 0.0;
  for (int i = 0; i < model.mass_count; ++i) {
    sx += state.x[i];
    sy += state.y[i];
  }
  return {sx / model.mass_count, sy / model.mass_count};
}

} // namespace soda
