#include <cstdio>
#include <map>
#include <memory>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "core/sine_identity.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_sine.hpp"

namespace sodaevo::app {

namespace {

struct ReplayOptions {
  std::string run;
  int generation = -1;
  int threads = 0;
};

int run_replay(const ReplayOptions& opt) {
  const std::filesystem::path run(opt.run);
  const RunConfig config = read_run_config(run / "config.json");
  int generation = opt.generation;
  if (generation < 0) {
    const std::vector<int> saved = saved_generations(run);
    if (saved.empty()) throw soda::InputError(opt.run + ": no saved generation to replay");
    generation = saved.back();
  }
  const Generation g = read_saved_generation(run, generation);
  const RunRoles roles = roles_of(config);
  // With the race timeout the generation was scored with (evolve/runs/race_schedule.hpp).
  const std::unique_ptr<Problem> scheduled = scheduled_problem(*roles.problem, g);
  const Problem& problem = scheduled ? *scheduled : *roles.problem;
  // Each creature on as many replicas as it was logged with (survivors gather
  // more, evolve/estimators/replica_estimator.hpp): one evaluation per replica count.
  std::map<int, std::vector<std::size_t>> by_rollouts;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    by_rollouts[g.individuals[i].evaluation.estimate.rollouts].push_back(i);
  }
  ThreadEvaluator evaluator(opt.threads);
  std::vector<Evaluation> replayed(g.individuals.size());
  for (const auto& [rollouts, who] : by_rollouts) {
    std::vector<const soda::ModelDef*> creatures;
    for (std::size_t i : who) creatures.push_back(&g.individuals[i].creature);
    std::unique_ptr<Estimator> logged_count = rollouts > 0 ? roles.estimator->with_rollouts(rollouts) : nullptr;
    const Estimator& estimator = logged_count ? *logged_count : *roles.estimator;
    std::vector<Evaluation> r = evaluator.evaluate(creatures, problem, estimator);
    for (std::size_t k = 0; k < who.size(); ++k) replayed[who[k]] = std::move(r[k]);
  }
  // Made with another sine, the logged fitnesses are not this engine's to reproduce:
  // say so, show this engine's figures, compare nothing.
  const RunSine sine = read_run_sine(run);
  const std::string other = other_sine_note("generation " + std::to_string(generation) + " of this run was made",
                                            sine.of_generation(generation), sine.recorded);
  if (!other.empty()) {
    std::printf("note: %s, and that is no fault of the run; the figures below are this engine's and are not "
                "compared with the logged ones.\n",
                other.c_str());
    std::size_t scored = 0, best = replayed.size();
    for (std::size_t i = 0; i < replayed.size(); ++i) {
      if (!replayed[i].ok()) continue;
      ++scored;
      if (best == replayed.size() || replayed[i].fitness > replayed[best].fitness) best = i;
    }
    std::printf("generation %d: %zu creatures re-simulated with this engine's sine, %zu scored", generation,
                replayed.size(), scored);
    if (best < replayed.size()) {
      std::printf("; best now %s fitness %s", g.individuals[best].id.c_str(),
                  soda::format_double_plain(replayed[best].fitness).c_str());
    }
    std::printf("\n");
    return 0;
  }
  int mismatches = 0;
  for (std::size_t i = 0; i < replayed.size(); ++i) {
    const Evaluation& logged = g.individuals[i].evaluation;
    const Evaluation& now = replayed[i];
    const bool same = logged.status == now.status &&
                      (!now.ok() || soda::format_double_plain(logged.fitness) == soda::format_double_plain(now.fitness));
    if (!same) {
      ++mismatches;
      std::printf("MISMATCH %s: logged %s, replayed %s %s\n", g.individuals[i].id.c_str(),
                  soda::format_double_plain(logged.fitness).c_str(), soda::format_double_plain(now.fitness).c_str(),
                  now.reason.c_str());
    }
  }
  std::printf("generation %d: %zu creatures replayed, %zu reproduce the logged fitness exactly, %d differ\n", generation,
              replayed.size(), replayed.size() - static_cast<std::size_t>(mismatches), mismatches);
  return mismatches == 0 ? 0 : 3;
}

} // namespace

void add_replay_command(CLI::App& app) {
  auto opt = std::make_shared<ReplayOptions>();
  CLI::App* cmd = app.add_subcommand(
      "replay",
      "Re-simulate every creature of a saved generation and check that each reproduces its\n"
      "logged fitness bit for bit (exit code 3 if any differs). A generation made with another\n"
      "muscle sine (manifest.json; runs made before " + std::string(soda::kGlibcSineUntil) +
          " used glibc's sin, this engine computes\n"
          "Java's Math.sin) cannot reproduce: replay says so, prints this engine's figures, compares\n"
          "nothing and exits 0.");
  cmd->add_option("run", opt->run, "Run folder")->required()->check(non_empty_path())->check(CLI::ExistingDirectory);
  cmd->add_option("--generation,-g", opt->generation, "Saved generation to replay (default: the last saved)")
      ->check(CLI::Range(0, 100000000));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->callback([opt] {
    const int code = run_replay(*opt);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

} // namespace sodaevo::app
