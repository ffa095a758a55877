#include "map_elites.hpp"

#include <string>

#include "evolve/rng.hpp"
#include "evolve/variation.hpp"

namespace sodaevo {

namespace {

/// The axes' descriptors of one rollout, added to an entry's estimates.
void add_rollout(ArchiveEntry& entry, const GridArchive& archive, const DescribedEvaluation& d) {
  entry.fitness.add(d.evaluation.fitness);
  for (std::size_t a = 0; a < archive.axes().size(); ++a) {
    entry.descriptors[a].add(d.behaviour[static_cast<std::size_t>(archive.axes()[a].descriptor)]);
  }
}

/// Adds replicas [n, n + count) to `entry`; false if one of them failed (a
/// creature that diverges on another machine's sine is no elite).
bool gather(ArchiveEntry& entry, const GridArchive& archive, long long count, const ReplicaSampler& sample,
            long long& resampled) {
  const std::vector<DescribedEvaluation> more = sample(entry.creature, entry.fitness.n, count);
  resampled += static_cast<long long>(more.size());
  for (const DescribedEvaluation& d : more) {
    if (!d.evaluation.ok()) return false;
    add_rollout(entry, archive, d);
  }
  return true;
}

} // namespace

std::vector<Individual> map_elites_children(const RunConfig& config, const MapElitesConfig& me,
                                            const GridArchive& archive, int iteration) {
  std::vector<const ArchiveEntry*> elites;
  for (const auto& [cell, e] : archive.elites()) elites.push_back(&e);
  std::vector<Individual> children;
  if (elites.empty()) return children;
  for (int k = 0; k < me.batch_size; ++k) {
    Rng rng = Rng::stream(config.seed, static_cast<std::uint64_t>(iteration), static_cast<std::uint64_t>(k),
                          kMapElitesPurpose);
    const ArchiveEntry& a = *elites[rng.below(elites.size())];
    Individual child;
    // Appended piece by piece: "i" + std::string trips GCC 12's -Wrestrict (a false positive).
    child.id = std::to_string(iteration);
    child.id.insert(0, 1, 'i');
    child.id += '-';
    child.id += std::to_string(k);
    child.parents = {a.id};
    if (me.crossover_rate > 0.0 && rng.chance(me.crossover_rate)) {
      const ArchiveEntry& b = *elites[rng.below(elites.size())];
      child.creature = crossover(a.creature, b.creature, config, rng);
      child.parents.push_back(b.id);
    } else {
      child.creature = a.creature;
    }
    mutate(child.creature, config, rng);
    children.push_back(std::move(child));
  }
  return children;
}

InsertionCounts insert_challengers(GridArchive& archive, std::vector<Challenger> challengers, int iteration,
                                   long long cap, const ReplicaSampler& sample) {
  InsertionCounts counts;
  for (Challenger& c : challengers) {
    if (!c.first.evaluation.ok()) {
      ++counts.rejected;
      continue;
    }
    ArchiveEntry entry;
    entry.id = c.individual.id;
    entry.parents = c.individual.parents;
    entry.creature = std::move(c.individual.creature);
    entry.iteration = iteration;
    entry.distance = c.first.evaluation.distance;
    entry.descriptors.resize(archive.axes().size());
    add_rollout(entry, archive, c.first);
    // The cell of the first estimate, kept while the challenger is resampled.
    const std::size_t cell = archive.cell_of(c.first.behaviour);
    for (;;) {
      ArchiveEntry* elite = archive.elite(cell);
      const Judgement j = judge(elite != nullptr ? &elite->fitness : nullptr, entry.fitness, cap);
      if (j.verdict == Verdict::Enter || j.verdict == Verdict::Replace) {
        ++(j.verdict == Verdict::Enter ? counts.entered : counts.replaced);
        archive.place(cell, std::move(entry));
        break;
      }
      if (j.verdict == Verdict::Reject) {
        ++counts.rejected;
        break;
      }
      if (j.verdict == Verdict::SampleChallenger) {
        if (!gather(entry, archive, j.replicas, sample, counts.resampled)) {
          ++counts.rejected;
          break;
        }
      } else if (!gather(*elite, archive, j.replicas, sample, counts.resampled)) {
        // The elite failed on a fresh replica: the challenger takes the cell.
        ++counts.replaced;
        archive.place(cell, std::move(entry));
        break;
      }
    }
  }
  return counts;
}

} // namespace sodaevo
