#include "evolve/runs/archive_check.hpp"

#include "core/input_error.hpp"
#include "evolve/store/archive_store.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo {

std::vector<Individual> archive_individuals(const GridArchive& archive) {
  std::vector<Individual> out;
  for (const auto& [cell, e] : archive.elites()) {
    Individual ind;
    ind.id = e.id;
    ind.parents = e.parents;
    ind.creature = e.creature;
    ind.evaluated = true;
    ind.evaluation.status = EvaluationStatus::Ok;
    ind.evaluation.fitness = e.fitness.mean;
    ind.evaluation.distance = e.distance;
    // The archive keeps no median: the mean stands in for it.
    ind.evaluation.estimate = {static_cast<int>(e.fitness.n), e.fitness.mean, e.fitness.sd(), e.fitness.mean};
    out.push_back(std::move(ind));
  }
  return out;
}

CheckedArchive check_archive(const GridArchive& archive, const Problem& problem, const ReplicaPlan& plan,
                             int replicas, int threads, double qd_offset) {
  CheckedArchive c;
  const std::vector<Individual> elites = archive_individuals(archive);
  c.checks = check_all_on_fresh_replicas(problem, elites, plan, replicas, threads);
  GridArchive checked(archive.axes());
  double curse = 0.0;
  int counted = 0;
  std::size_t i = 0;
  for (const auto& [cell, e] : archive.elites()) {
    c.cells.push_back(cell);
    const ReplicaCheck& check = c.checks[i++];
    if (!check.ok) continue;
    ArchiveEntry entry = e;
    entry.fitness = RunningEstimate{};
    entry.fitness.merge(check.check.n, e.fitness.mean - check.winners_curse, 0.0);
    checked.place(cell, std::move(entry));
    curse += check.winners_curse;
    ++counted;
  }
  c.selection = archive.metrics(qd_offset);
  c.checked = checked.metrics(qd_offset);
  c.mean_winners_curse = counted > 0 ? curse / counted : 0.0;
  return c;
}

GridArchive read_run_archive(const std::filesystem::path& run_dir, const RunConfig& config) {
  GridArchive archive(config.map_elites.axes);
  if (!ArchiveStore(run_dir).read_checkpoint(archive)) {
    throw soda::InputError((run_dir / "archive_checkpoint.json").string() +
                           ": missing: not a MAP-Elites run folder, or it has not finished its first iteration");
  }
  return archive;
}

CheckedArchive write_checked_archive(const std::filesystem::path& run_dir, int threads) {
  const RunConfig config = read_run_config(run_dir / "config.json");
  const MapElitesConfig& me = config.map_elites;
  const GridArchive archive = read_run_archive(run_dir, config);
  const std::unique_ptr<Problem> problem = problem_of(config, 0);
  const CheckedArchive c =
      check_archive(archive, *problem, replica_plan(config), me.check_replicas, threads, me.qd_offset);
  nlohmann::json cells = nlohmann::json::array();
  for (std::size_t i = 0; i < c.cells.size(); ++i) {
    const ArchiveEntry& e = *archive.elite(c.cells[i]);
    nlohmann::json j = champion_json(c.checks[i], elite_file(e.id), config);
    j["cell"] = c.cells[i];
    if (c.checks[i].ok) j["checked_fitness"] = e.fitness.mean - c.checks[i].winners_curse;
    cells.push_back(std::move(j));
  }
  const nlohmann::json out = {{"format", "sodaevo-archive-checked-1"},
                              {"check_replicas", me.check_replicas},
                              {"qd_offset", me.qd_offset},
                              {"metrics", {{"selection", metrics_to_json(c.selection)}, {"checked", metrics_to_json(c.checked)}}},
                              {"mean_winners_curse", c.mean_winners_curse},
                              {"cells", cells}};
  soda::write_file_atomically(run_dir / "archive_checked.json", out.dump(1) + "\n");
  return c;
}

} // namespace sodaevo
