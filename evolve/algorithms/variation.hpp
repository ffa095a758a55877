// Variation: how new creatures are made. Random creatures, mutation operators
// (each with its rate in MutationConfig) and optional one-point crossover.
//
// Every operator keeps the creature valid: masses only, connected, within the
// limits, amplitudes in [0, 1], phases in [0, 1). Results are in canonical form
// (soda::canonical_form), so writing a creature to XML and reading it back gives
// exactly the same creature, link order included, and so the same fitness.
#pragma once

#include "core/model_def.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/algorithms/genetic_settings.hpp"

namespace sodaevo {

/// A random connected creature (spanning tree plus extra links) in the config's world.
soda::ModelDef random_creature(const GeneticSettings& config, Rng& rng);

/// Applies each mutation operator with its rate (at least one change is made).
/// Operators that would break validity are skipped.
void mutate(soda::ModelDef& creature, const GeneticSettings& config, Rng& rng);

/// One-point crossover on mass order: the child has the first k masses of `a` and
/// the masses of `b` from index k on; links of `a` among its first k masses and
/// links of `b` touching its masses from k on (ends below k mapped to a's masses of
/// the same index); world and wave from `a`. Components left apart are joined by a
/// spring between their nearest masses. The result is checked against the limits;
/// if it fails, a copy of `a` is returned.
soda::ModelDef crossover(const soda::ModelDef& a, const soda::ModelDef& b, const GeneticSettings& config, Rng& rng);

/// A seed model made fit for evolution: fixed nodes and fixed bars removed, then
/// only the largest connected piece kept, canonical form. Throws soda::InputError
/// if nothing valid remains.
soda::ModelDef creature_from_seed(const soda::ModelDef& seed, const GeneticSettings& config);

} // namespace sodaevo
