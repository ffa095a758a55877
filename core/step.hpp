// One frame of the SodaConstructor engine (docs/physics.md, "One frame").
//
// This is the reference step: a plain loop over the rules in physics_rules.hpp in
// the original's order. Faster steppers must equal it bit for bit.
#pragma once

#include "model.hpp"

namespace soda {

/// Advances `state` by one frame: links in file order with immediate velocity
/// impulses, then each mass in order (gravity, friction, rest test, move, container,
/// fixed bars, autoreverse), then the wave advance.
void step(const Model& model, State& state);

/// Steps `frames` frames.
void run(const Model& model, State& state, long long frames);

/// The numbers of one semi-implicit Euler step of `dt` frames. The original's frame
/// is dt = 1 with the model's own values; the `continuous` mode's Euler takes
/// dt = 1/substeps with each rate scaled to the step (continuous_step.hpp).
struct EulerStep {
  double dt = 1.0;
  double gravity = 0.0;          ///< g*dt
  double keep = 1.0;             ///< share of velocity air friction leaves, (1 - f)^dt
  double surface_friction = 1.0; ///< Fs^dt
  double wave_step = 0.0;        ///< wave speed*dt
};

/// One step in the order of step() (which is this with dt = 1: every product by
/// dt is then exact). Leaves state.frame alone.
void euler_step(const Model& model, State& state, const EulerStep& e);

} // namespace soda
