// Divergence detection: telling a creature that the numerics blew up from one that
// merely moves a lot, with the frame and the reason, so that a run can mark it and
// go on (evolution finds and exploits every energy leak; Sims 1994).
//
// Two signs of divergence:
// - a non-finite number in the state (possible with legal but absurd inputs, e.g.
//   rest lengths near the largest double: the impulse overflows, the syrup factor
//   becomes 0, and 0 * inf is NaN);
// - runaway energy: more mechanical energy than the creature could have been given.
//   Energy E = kinetic (1/2 |v|^2 per mass) + springs (1/2 k (L - D)^2 per link,
//   D the muscle's current target) + gravity (g times the height above the floor,
//   or below the ceiling when gravity points up; positions clamped into the
//   container). Only muscles supply energy: a muscle changes its target at rate
//   |dD/dt| <= |R| Aw Am 2 pi |speed|, so it supplies at most k |L - D| |dD/dt| per
//   frame. Air friction takes exactly 1 - (1 - f)^2 of the kinetic energy per
//   frame. The monitor keeps an energy budget B (energy at the start, plus the
//   muscles' bound, minus friction's share, every frame) and flags a runaway when
//   E > factor * B + slack. Contact and the syrup limit only take energy, so a
//   stable integration stays below B up to its (bounded) energy error; an unstable
//   one (e.g. a stiff cluster under one-step-per-frame Euler) grows past it.
#pragma once

#include <optional>
#include <string>

#include "model.hpp"

namespace soda {

struct DivergenceLimits {
  double energy_factor = 4.0;          ///< flag when E > factor * budget + slack
  double energy_slack_per_mass = 50.0; ///< px^2/frame^2 per free mass (a quarter of the syrup's 200)
};

struct Divergence {
  bool diverged = false;
  long long frame = 0; ///< frame at which it was first seen
  std::string reason;  ///< e.g. "non-finite vx of mass 3", "energy runaway: ..."
};

/// The engine's one finite-state check: the first free mass (in mass order) whose
/// position or velocity is not finite, or -1 if there is none. Every caller that
/// asks whether a creature blew up asks this (the monitor below, the fitness).
int first_non_finite_mass(const Model& model, const State& state);

/// The first non-finite position or velocity of a free mass (first_non_finite_mass),
/// or the wave phase, named ("vx of mass 3"); nullopt if all are finite.
std::optional<std::string> first_non_finite(const Model& model, const State& state);

/// Mechanical energy as defined above, px^2/frame^2 (mass 1).
double mechanical_energy(const Model& model, const State& state);

/// Upper bound of the power all muscles can supply in the state, px^2/frame^3.
double muscle_power_bound(const Model& model, const State& state);

/// Watches a run frame by frame: construct with the initial state, call check()
/// after every frame. Once diverged it stays diverged (result() keeps the first).
class DivergenceMonitor {
public:
  DivergenceMonitor(const Model& model, const State& initial, DivergenceLimits limits = {},
                    bool check_energy = true);
  /// Returns true while the run is healthy.
  bool check(const State& state);
  [[nodiscard]] const Divergence& result() const { return result_; }

private:
  const Model& model_;
  DivergenceLimits limits_;
  bool check_energy_;
  double kinetic_loss_share_; ///< 1 - (1 - f)^2
  double budget_ = 0.0;
  double power_ = 0.0;   ///< muscle power bound at the last checked state
  double kinetic_ = 0.0; ///< kinetic energy at the last checked state
  Divergence result_;
};

} // namespace soda
