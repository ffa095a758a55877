#include "genetic_algorithm.hpp"

#include <algorithm>
#include <string>

#include "evolve/algorithms/rng.hpp"
#include "evolve/algorithms/variation.hpp"

namespace sodaevo {

namespace {

std::string make_id(int generation, std::size_t index) {
  return "g" + std::to_string(generation) + "-" + std::to_string(index);
}

std::size_t tournament(const Generation& g, int size, Rng& rng) {
  std::size_t winner = rng.below(g.individuals.size());
  for (int k = 1; k < size; ++k) {
    const std::size_t challenger = rng.below(g.individuals.size());
    if (ranks_before(g, challenger, winner)) winner = challenger;
  }
  return winner;
}

} // namespace

Generation initial_generation(const GeneticSettings& config, const std::vector<soda::ModelDef>& seeds) {
  Generation g;
  g.index = 0;
  const int n = config.population.size;
  const int random_count = seeds.empty()
                               ? n
                               : static_cast<int>(std::lround(config.population.random_fraction * n));
  const int seeded_count = n - random_count;
  for (int i = 0; i < n; ++i) {
    Rng rng = Rng::stream(config.seed, 0, static_cast<std::uint64_t>(i), static_cast<std::uint64_t>(RngPurpose::Initial));
    Individual ind;
    ind.id = make_id(0, static_cast<std::size_t>(i));
    if (i < seeded_count) {
      const std::size_t s = static_cast<std::size_t>(i) % seeds.size();
      ind.creature = seeds[s];
      // Each seed enters once unchanged; further copies are mutated.
      if (static_cast<std::size_t>(i) >= seeds.size()) mutate(ind.creature, config, rng);
    } else {
      ind.creature = random_creature(config, rng);
    }
    g.individuals.push_back(std::move(ind));
  }
  return g;
}

Generation next_generation(const GeneticSettings& config, const Generation& evaluated) {
  Generation next;
  next.index = evaluated.index + 1;
  const std::size_t n = static_cast<std::size_t>(config.population.size);
  const std::vector<std::size_t> ranked = ranked_best_first(evaluated);

  const std::size_t elites = std::min<std::size_t>(static_cast<std::size_t>(config.selection.elites), ranked.size());
  for (std::size_t e = 0; e < elites; ++e) {
    const Individual& parent = evaluated.individuals[ranked[e]];
    if (!parent.evaluation.ok()) break; // never keep an invalid creature as an elite
    Individual copy = parent;
    copy.id = make_id(next.index, next.individuals.size());
    copy.parents = {parent.id};
    next.individuals.push_back(std::move(copy)); // evaluated stays true: not re-evaluated
  }
  while (next.individuals.size() < n) {
    const std::size_t i = next.individuals.size();
    Rng rng = Rng::stream(config.seed, static_cast<std::uint64_t>(next.index), i, static_cast<std::uint64_t>(RngPurpose::Breed));
    const std::size_t a = tournament(evaluated, config.selection.tournament_size, rng);
    Individual child;
    child.id = make_id(next.index, i);
    child.parents = {evaluated.individuals[a].id};
    if (config.crossover_rate > 0.0 && rng.chance(config.crossover_rate)) {
      const std::size_t b = tournament(evaluated, config.selection.tournament_size, rng);
      child.creature = crossover(evaluated.individuals[a].creature, evaluated.individuals[b].creature, config, rng);
      child.parents.push_back(evaluated.individuals[b].id);
    } else {
      child.creature = evaluated.individuals[a].creature;
    }
    mutate(child.creature, config, rng);
    next.individuals.push_back(std::move(child));
  }
  return next;
}

} // namespace sodaevo
