#include "divergence.hpp"

#include <algorithm>
#include <cmath>

#include "number_text.hpp"
#include "physics_rules.hpp"

namespace soda {

int first_non_finite_mass(const Model& model, const State& state) {
  for (int i = 0; i < model.mass_count; ++i) {
    if (!std::isfinite(state.x[i]) || !std::isfinite(state.y[i]) || !std::isfinite(state.vx[i]) ||
        !std::isfinite(state.vy[i])) {
      return i;
    }
  }
  return -1;
}

std::optional<std::string> first_non_finite(const Model& model, const State& state) {
  if (!std::isfinite(state.wave_phase)) return std::string("wave phase");
  const int i = first_non_finite_mass(model, state);
  if (i < 0) return std::nullopt;
  const char* what = !std::isfinite(state.x[i])   ? "x"
                     : !std::isfinite(state.y[i]) ? "y"
                     : !std::isfinite(state.vx[i]) ? "vx"
                                                   : "vy";
  return std::string(what) + " of mass " + std::to_string(i);
}

namespace {

double kinetic_energy(const Model& m, const State& s) {
  double e = 0.0;
  for (int i = 0; i < m.mass_count; ++i) e += 0.5 * (s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i]);
  return e;
}

double link_target(const Model& m, const State& s, int i) {
  return rules::link_target_length(m, i, s.wave_phase, s.jitter);
}

double link_length(const Model& m, const State& s, int i) {
  const double dx = s.x[m.link_b[i]] - s.x[m.link_a[i]];
  const double dy = s.y[m.link_b[i]] - s.y[m.link_a[i]];
  return std::sqrt(dx * dx + dy * dy);
}

} // namespace

double mechanical_energy(const Model& m, const State& s) {
  double e = kinetic_energy(m, s);
  for (int i = 0; i < m.link_count(); ++i) {
    const double stretch = link_length(m, s, i) - link_target(m, s, i);
    e += 0.5 * m.springyness * stretch * stretch;
  }
  const double g = m.gravity_step;
  for (int i = 0; i < m.mass_count; ++i) {
    const double y = std::clamp(s.y[i], 0.0, m.height);
    e += g >= 0.0 ? g * y : -g * (m.height - y);
  }
  return e;
}

double muscle_power_bound(const Model& m, const State& s) {
  const double rate = m.wave_amplitude * kTwoPi * std::fabs(m.wave_speed);
  double p = 0.0;
  for (int i = 0; i < m.link_count(); ++i) {
    if (!m.link_muscle[i]) continue;
    const double stretch = link_length(m, s, i) - link_target(m, s, i);
    p += m.springyness * std::fabs(stretch) * std::fabs(m.link_rest[i]) * m.link_amplitude[i] * rate;
  }
  return p;
}

DivergenceMonitor::DivergenceMonitor(const Model& model, const State& initial, DivergenceLimits limits,
                                     bool check_energy)
    : model_(model), limits_(limits), check_energy_(check_energy) {
  const double keep = model.air_keep;
  kinetic_loss_share_ = 1.0 - keep * keep;
  if (!check_energy_ || first_non_finite(model, initial)) return;
  budget_ = mechanical_energy(model, initial);
  power_ = muscle_power_bound(model, initial);
  kinetic_ = kinetic_energy(model, initial);
}

bool DivergenceMonitor::check(const State& s) {
  if (result_.diverged) return false;
  if (const auto bad = first_non_finite(model_, s)) {
    result_ = {true, s.frame, "non-finite " + *bad};
    return false;
  }
  if (!check_energy_) return true;
  const double energy = mechanical_energy(model_, s);
  if (!std::isfinite(energy)) {
    result_ = {true, s.frame, "non-finite energy"};
    return false;
  }
  // Frame 1 may clamp masses placed outside the container into it (the original
  // does so too): whatever energy that adds is part of the start.
  budget_ = std::max(0.0, budget_ + power_ - kinetic_loss_share_ * kinetic_);
  if (s.frame <= 1) budget_ = std::max(budget_, energy);
  power_ = muscle_power_bound(model_, s);
  kinetic_ = kinetic_energy(model_, s);
  const double limit = limits_.energy_factor * budget_ + limits_.energy_slack_per_mass * model_.mass_count;
  if (energy > limit) {
    result_ = {true, s.frame,
               "energy runaway: " + format_double_plain(energy) + " px^2/frame^2, more than " +
                   format_double_plain(limits_.energy_factor) + " x the budget " + format_double_plain(budget_) +
                   " that the start and the muscles allow (+ slack)"};
    return false;
  }
  return true;
}

} // namespace soda
