// Fitness honesty: does a creature walk because of its physics or because of the
// integration error of its step? Re-evaluate it with `factor` times the sub-steps
// (the soda mode's one update per frame becomes continuous Euler with `factor`
// steps per frame) and report the relative change in distance walked. A creature
// whose walk changes a lot when the step shrinks is exploiting the numerics
// (Sims 1994: "any bug that allows energy leaks will be discovered and exploited").
#pragma once

#include "core/stepping.hpp"

namespace sodaevo {

/// The same integration with `factor` times the sub-steps (capped at
/// kMaxSubsteps); soda mode becomes continuous Euler with `factor` sub-steps.
soda::Stepping refined_stepping(const soda::Stepping& stepping, int factor);

/// Distances below this (px) are not used as the denominator of a relative change:
/// a creature that barely moves has no meaningful relative error.
inline constexpr double kHonestyDistanceFloor = 1.0;

/// (refined - distance) / max(|refined|, kHonestyDistanceFloor): the signed share
/// by which the distance walked changes when the step is refined.
double relative_change(double distance, double refined_distance);

} // namespace sodaevo
