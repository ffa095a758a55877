// One frame of the SodaConstructor engine (spec 5.1).
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

} // namespace soda
