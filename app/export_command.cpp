#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/contender_filter.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/store/archive_store.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_reader.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "evolve/runs/run_roles.hpp"

namespace sodaevo::app {

namespace {

struct ExportOptions {
  std::string run;
  int best = 5;
  std::string out;
  bool archive = false;
  int check_replicas = 16;
  int threads = 0;
};

/// A race run's creature that falls apart: the GA may keep evolving it, but the
/// racer (and so the run's race fitness) races its largest piece alone.
void warn_if_in_pieces(const RunConfig& config, const soda::ModelDef& creature, const std::filesystem::path& file) {
  if (config.fitness.kind != FitnessKind::Race) return;
  const soda::ContenderPieces p = soda::contender_pieces(creature);
  if (p.connected()) return;
  std::cerr << "sodaevo: warning: " << file.string() << ": not one connected piece (" << p.pieces
            << " pieces): the original racer would race only its largest piece: " << p.kept.size() << " of "
            << p.masses << " masses\n";
}

/// Every elite of a MAP-Elites run's archive, as the run wrote it to RUN/elites/
/// (prepared as evaluated), named by cell, with the archive's index beside them,
/// and champions.json: each elite's estimate against a check on fresh replicas, as
/// for the GA's champions.
void export_archive(const std::filesystem::path& run, const ExportOptions& opt) {
  const std::filesystem::path index = run / "archive.json";
  if (!std::filesystem::exists(index)) {
    throw soda::InputError(index.string() + ": missing: --archive needs a MAP-Elites run folder");
  }
  const RunConfig config = read_run_config(run / "config.json");
  const GridArchive archive = read_run_archive(run, config);
  const std::unique_ptr<Problem> problem = problem_of(config, 0);
  const CheckedArchive checked = check_archive(archive, *problem, replica_plan(config), opt.check_replicas,
                                               opt.threads, config.map_elites.qd_offset);
  const std::filesystem::path out(opt.out);
  nlohmann::json champions = nlohmann::json::array();
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  const char* unit = score.unit;
  std::printf("cell    id            fitness (%s)   replicas   checked median [95 %% interval] (%s)   file\n",
              score.fitness_unit, unit);
  for (std::size_t i = 0; i < checked.cells.size(); ++i) {
    const std::size_t cell = checked.cells[i];
    const ArchiveEntry& e = *archive.elite(cell);
    const ReplicaCheck& c = checked.checks[i];
    const std::string name = "cell" + std::to_string(cell) + "_" + e.id + ".xml";
    soda::ModelDef prepared = soda::read_model_file(run / elite_file(e.id)).def;
    prepared.comment += "; " + check_comment(c, unit);
    soda::write_model_file(out / name, prepared);
    warn_if_in_pieces(config, prepared, out / name);
    nlohmann::json j = champion_json(c, name, config);
    j["cell"] = cell;
    champions.push_back(std::move(j));
    std::printf("%6zu  %-12s  %12.3f   %8lld   %10.3f [%.3f, %.3f]%s   %s\n", cell, e.id.c_str(), e.fitness.mean,
                e.fitness.n, c.check.median, c.check.interval95_low, c.check.interval95_high,
                c.ok ? "" : " (check failed)", (out / name).string().c_str());
  }
  soda::write_file_atomically(out / "archive.json", soda::read_whole_file(index));
  soda::write_file_atomically(out / "champions.json", champions.dump(2) + "\n");
  std::printf("champions.json: each elite's estimate against a check on %d fresh replicas; checked archive: "
              "QD-score %.1f (run's %.1f), best fitness %.2f (run's %.2f) %s\n",
              opt.check_replicas, checked.checked.qd_score, checked.selection.qd_score, checked.checked.best,
              checked.selection.best,
              score.lower_is_better ? ("(minus " + std::string(score.unit) + ")").c_str() : score.fitness_unit);
}

void run_export(const ExportOptions& opt) {
  const std::filesystem::path run(opt.run);
  const RunConfig config = read_run_config(run / "config.json");
  const std::unique_ptr<Problem> problem = final_problem(run, config); // a curriculum's last stage
  std::error_code ec;
  std::filesystem::create_directories(opt.out, ec);
  if (ec) throw soda::InputError(opt.out + ": cannot create the folder: " + ec.message());
  if (opt.archive) return export_archive(run, opt);
  const std::vector<Individual> best = best_individuals(run, opt.best);
  // Each creature again on fresh replicas that selection never saw: what it
  // claims against what it walks (evolve/runs/replica_check.hpp).
  const std::vector<ReplicaCheck> checks =
      check_all_on_fresh_replicas(*problem, best, replica_plan(config), opt.check_replicas, opt.threads);
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  const std::string unit = score.unit;
  std::printf("rank  id            fitness (%s)   replicas   checked median [95 %% interval] (%s)   file\n",
              score.fitness_unit, unit.c_str());
  nlohmann::json champions = nlohmann::json::array();
  for (std::size_t i = 0; i < best.size(); ++i) {
    const Individual& ind = best[i];
    const ExportedChampion exported =
        export_ranked_champion(*problem, ind, checks[i], config, unit, opt.out, static_cast<int>(i + 1));
    const std::filesystem::path& file = exported.file;
    warn_if_in_pieces(config, exported.prepared, file);
    champions.push_back(exported.entry);
    const ReplicaCheck& c = checks[i];
    std::printf("%4zu  %-12s  %12.3f   %8d   %10.3f [%.3f, %.3f]%s   %s\n", i + 1, ind.id.c_str(), ind.evaluation.fitness,
                ind.evaluation.estimate.rollouts, c.check.median, c.check.interval95_low, c.check.interval95_high,
                c.ok ? "" : " (check failed)", file.string().c_str());
  }
  soda::write_file_atomically(std::filesystem::path(opt.out) / "champions.json", champions.dump(2) + "\n");
  std::printf("champions.json: selection against the check on %d fresh replicas each\n", opt.check_replicas);
}

} // namespace

void add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write the best creatures of a run (of its last saved generation, the one it ended with;\n"
      "its best are confirmed on /fitness/replicas_max replicas) as SodaConstructor v1 XML,\n"
      "prepared exactly as they were evaluated (world, Sodarace scaling, wide container, wave\n"
      "forward, autoreverse off),\n"
      "so SodaConstructor and `sodaevo simulate` run them the same way, and DIR/champions.json:\n"
      "each creature's claim (its estimate in the run) against a check on fresh replicas\n"
      "(n, mean, median, sd, min, max, 95 % prediction interval) and the winner's curse.");
  cmd->add_option("run", opt->run, "Run folder")->required()->check(non_empty_path())->check(CLI::ExistingDirectory);
  cmd->add_option("--best", opt->best, "How many distinct creatures")->default_val(5)->check(CLI::Range(1, 100000));
  cmd->add_option("--out", opt->out, "Output folder")->required();
  cmd->add_flag("--archive", opt->archive,
                "A MAP-Elites run: every elite of its archive (DIR/cell<N>_<id>.xml), DIR/archive.json\n"
                "and DIR/champions.json (each elite checked on fresh replicas)");
  cmd->add_option("--check-replicas", opt->check_replicas,
                  "Fresh replicas (sine-jitter seeds never used in selection) each exported creature is\n"
                  "re-run on for champions.json and the XML comment: claimed against checked")
      ->default_val(16)
      ->check(CLI::Range(2, 4096));
  cmd->add_option("--threads", opt->threads, "Threads for the check (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->callback([opt] { run_export(*opt); });
}

} // namespace sodaevo::app
