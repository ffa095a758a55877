#include "evolve/runs/replica_check.hpp"

#include <cstdio>
#include <exception>
#include <vector>

#include "core/number_text.hpp"
#include "evolve/config/race_fitness_config.hpp"
#include "evolve/evaluators/parallel_for.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"

namespace sodaevo {

ReplicaCheck check_on_fresh_replicas(const Problem& problem, const Individual& individual, const ReplicaPlan& plan,
                                     int replicas) {
  ReplicaCheck c;
  c.id = individual.id;
  c.selection = individual.evaluation.estimate;
  soda::ModelDef prepared;
  try {
    prepared = problem.prepare(individual.creature);
  } catch (const std::exception& ex) {
    c.reason = ex.what();
    return c;
  }
  const std::uint64_t key = creature_key(individual.creature);
  std::vector<Rollout> runs{Rollout(&prepared)}; // exact
  for (int r = 0; r < replicas; ++r) {
    runs.emplace_back(&prepared, soda::SineJitter{replica_seed(plan.run_seed, ReplicaPurpose::Check, key, r), plan.jitter});
  }
  const std::vector<Evaluation> done = problem.rollouts(runs);
  std::vector<double> distances, fitness;
  for (std::size_t i = 0; i < done.size(); ++i) {
    if (!done[i].ok()) {
      c.reason = (i == 0 ? std::string("exact run: ") : "check replica " + std::to_string(i - 1) + ": ") + done[i].reason;
      return c;
    }
    if (i == 0) continue;
    distances.push_back(done[i].distance);
    fitness.push_back(done[i].fitness);
  }
  c.exact_distance = done[0].distance;
  c.check = summarize_sample(distances);
  c.winners_curse = c.selection.mean - summarize_sample(fitness).mean;
  c.ok = true;
  return c;
}

std::vector<ReplicaCheck> check_all_on_fresh_replicas(const Problem& problem, const std::vector<Individual>& individuals,
                                                      const ReplicaPlan& plan, int replicas, int threads) {
  std::vector<ReplicaCheck> checks(individuals.size());
  parallel_for_index(individuals.size(), threads, [&](std::size_t i) {
    checks[i] = check_on_fresh_replicas(problem, individuals[i], plan, replicas);
  });
  return checks;
}

nlohmann::json champion_json(const ReplicaCheck& c, const std::string& file, long long settle_frames, long long frames) {
  nlohmann::json j = {{"file", file}, {"id", c.id}, {"settle_frames", settle_frames}, {"frames", frames}};
  if (!c.ok) {
    j["error"] = c.reason;
    return j;
  }
  j["exact_distance"] = c.exact_distance;
  j["selection"] = {{"n", c.selection.rollouts}, {"mean", c.selection.mean}, {"sd", c.selection.sd}};
  j["check"] = {{"n", c.check.n},       {"mean", c.check.mean}, {"median", c.check.median},
                {"sd", c.check.sd},     {"min", c.check.min},   {"max", c.check.max},
                {"interval95", {c.check.interval95_low, c.check.interval95_high}}};
  j["winners_curse"] = c.winners_curse;
  return j;
}

nlohmann::json champion_json(const ReplicaCheck& c, const std::string& file, const RunConfig& config) {
  nlohmann::json j = champion_json(c, file, config.fitness.settle_frames, config.fitness.frames);
  switch (config.fitness.kind) { // no default: a new kind says what its entry holds
    case FitnessKind::Walk: break;
    case FitnessKind::Race:
      j.erase("settle_frames");
      j.erase("frames");
      j["unit"] = fitness_kind_info(config.fitness.kind).unit;
      j["race"] = to_json(config.fitness.race);
      break;
  }
  return j;
}

std::vector<ReplicaCheck> write_run_champions(const std::filesystem::path& run_dir, int count, int replicas,
                                              int threads) {
  const RunConfig config = read_run_config(run_dir / "config.json");
  const std::vector<Individual> best = best_individuals(run_dir, count);
  const std::vector<ReplicaCheck> checks =
      check_all_on_fresh_replicas(*final_problem(run_dir, config), best, replica_plan(config), replicas, threads);
  nlohmann::json all = nlohmann::json::array();
  for (const ReplicaCheck& c : checks) {
    all.push_back(champion_json(c, "", config));
  }
  soda::write_file_atomically(run_dir / "champions.json", all.dump(2) + "\n");
  return checks;
}

std::string check_comment(const ReplicaCheck& c, const std::string& unit, int digits) {
  if (!c.ok) return "check on fresh replicas failed: " + c.reason;
  const auto number = [digits](double v) {
    if (digits < 0) return soda::format_double_plain(v);
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", digits, v);
    return std::string(text);
  };
  return "checked on " + std::to_string(c.check.n) + " fresh replicas: median " + number(c.check.median) + " " + unit +
         ", 95 % interval [" + number(c.check.interval95_low) + ", " + number(c.check.interval95_high) + "] " + unit +
         " (exact engine " + number(c.exact_distance) + " " + unit + ")";
}

ExportedChampion export_ranked_champion(const Problem& problem, const Individual& individual, const ReplicaCheck& check,
                                        const RunConfig& config, const std::string& unit,
                                        const std::filesystem::path& out_dir, int rank) {
  ExportedChampion out;
  out.prepared = problem.export_form(individual.creature, individual.id, individual.evaluation);
  out.prepared.comment += "; " + check_comment(check, unit);
  char name[64];
  std::snprintf(name, sizeof name, "rank%02d_%s.xml", rank, individual.id.c_str());
  out.name = name;
  out.file = out_dir / out.name;
  soda::write_model_file(out.file, out.prepared);
  out.entry = champion_json(check, out.name, config);
  return out;
}

} // namespace sodaevo
