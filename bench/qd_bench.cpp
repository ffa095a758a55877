#include "bench/qd_bench.hpp"

#include <chrono>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "core/input_error.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/map_elites_run.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/store/run_store.hpp"

namespace sodaevo::bench {

using charts::fixed;

namespace {

namespace fs = std::filesystem;

/// The GA's last population as an archive of the grid of `me`, inserted by the
/// same rule as MAP-Elites' children.
QdMetrics population_archive(const RunConfig& config, const MapElitesConfig& me, const Generation& population,
                             Evaluator& evaluator) {
  GridArchive archive(me.axes);
  std::vector<const soda::ModelDef*> creatures;
  for (const Individual& ind : population.individuals) creatures.push_back(&ind.creature);
  const WalkProblem problem = map_elites_problem(config, me);
  const ReplicaEstimator estimator(replica_plan(config));
  const std::vector<Evaluation> described = evaluator.evaluate(creatures, problem, estimator);
  std::vector<Challenger> challengers;
  for (std::size_t i = 0; i < creatures.size(); ++i) challengers.push_back({population.individuals[i], described[i]});
  insert_challengers(archive, std::move(challengers), 0, map_elites_resample_plan(replica_plan(config)),
                     replica_sampler(evaluator, problem, estimator));
  return archive.metrics(me.qd_offset);
}

double elapsed_seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double mean_of(const std::vector<QdRow>& rows, const std::string& algorithm, double (*get)(const QdRow&)) {
  double sum = 0.0;
  int n = 0;
  for (const QdRow& r : rows) {
    if (r.algorithm == algorithm) sum += get(r), ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

} // namespace

std::vector<QdRow> run_qd_bench(const QdOptions& opt) {
  if (opt.config.algorithm != AlgorithmKind::MapElites) {
    throw soda::InputError(opt.config_name + ": /algorithm: expected \"map-elites\" (bench qd compares its MAP-Elites "
                           "settings with the GA), got \"ga\"");
  }
  std::vector<QdRow> rows;
  for (const std::uint64_t seed : opt.seeds) {
    RunConfig me_config = opt.config;
    me_config.seed = seed;
    me_config.map_elites.check_replicas = opt.check_replicas;
    if (opt.iterations > 0) me_config.map_elites.iterations = opt.iterations;
    const fs::path me_dir = opt.work_dir / ("map-elites-seed" + std::to_string(seed));
    RunStore::create(me_dir, me_config, true, "sodaevo bench qd");
    ThreadEvaluator evaluator(opt.threads);
    auto started = std::chrono::steady_clock::now();
    const MapElitesOutcome me = run_map_elites(me_dir, me_config, me_config.map_elites, evaluator, {});
    QdRow me_row{seed, "map-elites", me.evaluations, me.metrics, 0.0, elapsed_seconds(started)};
    me_row.best_checked = write_checked_archive(me_dir, opt.threads).checked.best;
    rows.push_back(me_row);

    RunConfig ga_config = me_config;
    ga_config.algorithm = AlgorithmKind::Genetic;
    ga_config.budget.max_evaluations = me.evaluations;
    ga_config.budget.generations = 1000000;
    ga_config.save.generation_every = 0;
    ga_config.save.checkpoint_every = 1000000;
    const fs::path ga_dir = opt.work_dir / ("ga-seed" + std::to_string(seed));
    RunStore store = RunStore::create(ga_dir, ga_config, true, "sodaevo bench qd");
    started = std::chrono::steady_clock::now();
    const EvolutionOutcome ga = run_evolution(store, evaluator, {});
    const double ga_seconds = elapsed_seconds(started);
    const std::optional<Checkpoint> last = store.read_checkpoint();
    if (!last) throw std::runtime_error(ga_dir.string() + ": the GA run left no checkpoint");
    QdRow ga_row{seed, "ga", ga.evaluations,
                 population_archive(me_config, me_config.map_elites, last->generation, evaluator), 0.0, ga_seconds};
    const std::vector<Individual> best = best_individuals(ga_dir, 1);
    if (!best.empty()) {
      const ReplicaCheck c = check_on_fresh_replicas(walk_problem_of(ga_config), best.front(), replica_plan(ga_config),
                                                     opt.check_replicas);
      if (c.ok) ga_row.best_checked = c.selection.mean - c.winners_curse;
    }
    rows.push_back(ga_row);
    if (opt.progress) {
      for (const QdRow& r : {me_row, ga_row}) {
        opt.progress("seed " + std::to_string(seed) + "  " + r.algorithm + "  " + std::to_string(r.evaluations) +
                     " evaluations  filled " + std::to_string(r.metrics.filled) + " (" +
                     fixed(100.0 * r.metrics.coverage, 1) + " %)  QD-score " + fixed(r.metrics.qd_score, 0) +
                     "  best " + fixed(r.metrics.best, 1) + " (checked " + fixed(r.best_checked, 1) + ")  " +
                     fixed(r.seconds, 0) + " s");
      }
    }
  }
  return rows;
}

std::string qd_csv(const std::vector<QdRow>& rows) {
  std::string csv = "seed,algorithm,evaluations,cells,filled,coverage_percent,qd_score,normalized_qd_score,best,"
                    "mean_fitness,best_checked,seconds\n";
  for (const QdRow& r : rows) {
    const QdMetrics& m = r.metrics;
    csv += std::to_string(r.seed) + "," + r.algorithm + "," + std::to_string(r.evaluations) + "," +
           std::to_string(m.cells) + "," + std::to_string(m.filled) + "," + fixed(100.0 * m.coverage, 2) + "," +
           fixed(m.qd_score, 1) + "," + fixed(m.normalized_qd_score, 3) + "," + fixed(m.best, 2) + "," +
           fixed(m.mean, 2) + "," + fixed(r.best_checked, 2) + "," + fixed(r.seconds, 1) + "\n";
  }
  return csv;
}

std::string qd_svg(const std::vector<QdRow>& rows) {
  charts::BarChart chart;
  chart.title = "MAP-Elites vs GA at equal evaluations: QD-score per seed";
  chart.y_axis.label = "QD-score (sum of elite fitness, px)";
  chart.y_axis.min = 0.0;
  charts::BarSeries me_series{"MAP-Elites", {}}, ga_series{"GA (last population as an archive)", {}};
  for (const QdRow& r : rows) {
    if (r.algorithm == "map-elites") chart.categories.push_back("seed " + std::to_string(r.seed));
    (r.algorithm == "map-elites" ? me_series : ga_series).values.push_back(r.metrics.qd_score);
  }
  chart.series = {me_series, ga_series};
  return charts::render_bar_chart(chart);
}

std::string qd_markdown(const std::vector<QdRow>& rows, const QdOptions& opt, const std::string& command) {
  std::ostringstream md;
  const auto qd = [](const QdRow& r) { return r.metrics.qd_score; };
  const auto coverage = [](const QdRow& r) { return 100.0 * r.metrics.coverage; };
  const auto best = [](const QdRow& r) { return r.metrics.best; };
  const auto checked = [](const QdRow& r) { return r.best_checked; };
  const auto evaluations = [](const QdRow& r) { return static_cast<double>(r.evaluations); };
  const auto seconds = [](const QdRow& r) { return r.seconds; };
  md << "# MAP-Elites vs the GA at equal evaluations\n\n`" << command << "`\n\n"
     << "Config " << opt.config_name << ", " << opt.seeds.size() << " seeds, " << opt.config.fitness.replicas
     << " replicas per new creature (up to " << opt.config.fitness.replicas_max
     << "); the GA gets the evaluations MAP-Elites made (its population and selection from the config); its last "
     << "population counts as its archive, in the same grid (" << (rows.empty() ? 0 : rows.front().metrics.cells)
     << " cells). \"best, checked\": the best creature's mean fitness on " << opt.check_replicas
     << " fresh replicas that selection never saw (MAP-Elites: the best elite of the checked archive).\n\n"
     << "| algorithm | evaluations | coverage % | QD-score | best (px) | best, checked (px) | seconds |\n"
     << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const char* a : {"map-elites", "ga"}) {
    md << "| " << a << " (mean) | " << fixed(mean_of(rows, a, evaluations), 0) << " | "
       << fixed(mean_of(rows, a, coverage), 1) << " | " << fixed(mean_of(rows, a, qd), 0) << " | "
       << fixed(mean_of(rows, a, best), 1) << " | " << fixed(mean_of(rows, a, checked), 1) << " | "
       << fixed(mean_of(rows, a, seconds), 0) << " |\n";
  }
  const double ratio = mean_of(rows, "map-elites", best) / mean_of(rows, "ga", best);
  const double checked_ratio = mean_of(rows, "map-elites", checked) / mean_of(rows, "ga", checked);
  md << "\nMAP-Elites' best elite is " << fixed(100.0 * ratio, 1) << " % of the GA's best as estimated, "
     << fixed(100.0 * checked_ratio, 1) << " % as checked (means over seeds).\n\n"
     << "Per seed: qd.csv. Chart: qd.svg.\n";
  return md.str();
}

} // namespace sodaevo::bench
