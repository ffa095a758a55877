// sodaevo bench qd: MAP-Elites against the GA at equal evaluations (issue 28).
//
// For each seed, the config is run twice from the same initial creatures: as
// MAP-Elites (its /map_elites settings), then as the GA (its /population and
// /selection) with /budget/evaluations set to the evaluations MAP-Elites made. The
// GA's last population is put into an archive of the same grid (its creatures
// evaluated with their descriptors), so both get a QD-score, a coverage and a best
// fitness from the same definitions (evolve/grid_archive.hpp). Writes qd.csv,
// qd.md and qd.svg, and keeps the runs' folders under qd-runs/.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "core/input_error.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/evolution_run.hpp"
#include "evolve/map_elites_run.hpp"
#include "evolve/run_store.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

using charts::fixed;
using charts::BarChart;
using charts::BarSeries;
using charts::render_bar_chart;

namespace {

namespace fs = std::filesystem;

struct BenchQdOptions {
  std::string config = "configs/map_elites.json";
  int seeds = 5;
  int iterations = 0; ///< 0: the config's
  int threads = 0;
  std::string out = "results/bench";
};

struct QdResult {
  std::uint64_t seed = 0;
  std::string algorithm;
  long long evaluations = 0;
  QdMetrics metrics;
};

/// The GA's last population as an archive of the grid of `me`.
QdMetrics population_archive(const RunConfig& config, const MapElitesConfig& me, const Generation& population,
                             int threads) {
  GridArchive archive(me.axes);
  std::vector<Individual> individuals = population.individuals;
  std::vector<const soda::ModelDef*> creatures;
  for (const Individual& ind : individuals) creatures.push_back(&ind.creature);
  const std::vector<DescribedEvaluation> described = described_evaluator_on_threads(config, me, threads)(creatures);
  std::vector<Challenger> challengers;
  for (std::size_t i = 0; i < individuals.size(); ++i) challengers.push_back({individuals[i], described[i]});
  insert_challengers(archive, std::move(challengers), 0, 1, nullptr);
  return archive.metrics(me.qd_offset);
}

std::string results_csv(const std::vector<QdResult>& results) {
  std::string csv = "seed,algorithm,evaluations,cells,filled,coverage_percent,qd_score,normalized_qd_score,best,mean_fitness\n";
  for (const QdResult& r : results) {
    const QdMetrics& m = r.metrics;
    csv += std::to_string(r.seed) + "," + r.algorithm + "," + std::to_string(r.evaluations) + "," +
           std::to_string(m.cells) + "," + std::to_string(m.filled) + "," + fixed(100.0 * m.coverage, 2) + "," +
           fixed(m.qd_score, 1) + "," + fixed(m.normalized_qd_score, 3) + "," + fixed(m.best, 2) + "," +
           fixed(m.mean, 2) + "\n";
  }
  return csv;
}

double mean_of(const std::vector<QdResult>& results, const std::string& algorithm, double (*get)(const QdResult&)) {
  double sum = 0.0;
  int n = 0;
  for (const QdResult& r : results) {
    if (r.algorithm == algorithm) sum += get(r), ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

void run_bench_qd(const BenchQdOptions& opt, const std::string& command) {
  const RunConfig base = read_run_config(opt.config);
  if (base.algorithm != AlgorithmKind::MapElites) {
    throw soda::InputError(opt.config + ": /algorithm: expected \"map-elites\" (bench qd compares its MAP-Elites "
                           "settings with the GA), got \"ga\"");
  }
  const fs::path out(opt.out);
  const fs::path runs = out / "qd-runs";
  std::vector<QdResult> results;
  for (int s = 1; s <= opt.seeds; ++s) {
    RunConfig me_config = base;
    me_config.seed = static_cast<std::uint64_t>(s);
    if (opt.iterations > 0) me_config.map_elites.iterations = opt.iterations;
    const fs::path me_dir = runs / ("map-elites-seed" + std::to_string(s));
    RunStore::create(me_dir, me_config, true, command);
    const MapElitesOutcome me = run_map_elites(
        me_dir, me_config, me_config.map_elites,
        described_evaluator_on_threads(me_config, me_config.map_elites, opt.threads), {});
    results.push_back({me_config.seed, "map-elites", me.evaluations, me.metrics});

    RunConfig ga_config = me_config;
    ga_config.algorithm = AlgorithmKind::Genetic;
    ga_config.budget.max_evaluations = me.evaluations;
    ga_config.budget.generations = 1000000;
    ga_config.save.generation_every = 0;
    ga_config.save.checkpoint_every = 1000000;
    const fs::path ga_dir = runs / ("ga-seed" + std::to_string(s));
    RunStore store = RunStore::create(ga_dir, ga_config, true, command);
    ThreadEvaluator evaluator(opt.threads);
    const EvolutionOutcome ga = run_evolution(store, evaluator, {});
    const std::optional<Checkpoint> last = store.read_checkpoint();
    if (!last) throw std::runtime_error(ga_dir.string() + ": the GA run left no checkpoint");
    results.push_back(
        {ga_config.seed, "ga", ga.evaluations, population_archive(me_config, me_config.map_elites, last->generation, opt.threads)});
    for (std::size_t k = results.size() - 2; k < results.size(); ++k) {
      const QdResult& r = results[k];
      std::cerr << "seed " << s << "  " << r.algorithm << "  " << r.evaluations << " evaluations  filled "
                << r.metrics.filled << " (" << fixed(100.0 * r.metrics.coverage, 1) << " %)  QD-score "
                << fixed(r.metrics.qd_score, 0) << "  best " << fixed(r.metrics.best, 1) << "\n";
    }
  }

  BarChart chart;
  chart.title = "MAP-Elites vs GA at equal evaluations: QD-score per seed";
  chart.y_axis.label = "QD-score (sum of elite fitness, px)";
  chart.y_axis.min = 0.0;
  BarSeries me_series{"MAP-Elites", {}}, ga_series{"GA (last population as an archive)", {}};
  for (const QdResult& r : results) {
    if (r.algorithm == "map-elites") chart.categories.push_back("seed " + std::to_string(r.seed));
    (r.algorithm == "map-elites" ? me_series : ga_series).values.push_back(r.metrics.qd_score);
  }
  chart.series = {me_series, ga_series};

  std::ostringstream md;
  const auto qd = [](const QdResult& r) { return r.metrics.qd_score; };
  const auto coverage = [](const QdResult& r) { return 100.0 * r.metrics.coverage; };
  const auto best = [](const QdResult& r) { return r.metrics.best; };
  const auto evaluations = [](const QdResult& r) { return static_cast<double>(r.evaluations); };
  md << "# MAP-Elites vs the GA at equal evaluations\n\n`" << command << "`\n\n"
     << "Config " << opt.config << ", " << opt.seeds << " seeds; the GA gets the evaluations MAP-Elites made "
     << "(its population and selection from the config); its last population counts as its archive, in the same "
     << "grid (" << results.front().metrics.cells << " cells).\n\n"
     << "| algorithm | evaluations | coverage % | QD-score | best (px) |\n|---|---:|---:|---:|---:|\n";
  for (const char* a : {"map-elites", "ga"}) {
    md << "| " << a << " (mean) | " << fixed(mean_of(results, a, evaluations), 0) << " | "
       << fixed(mean_of(results, a, coverage), 1) << " | " << fixed(mean_of(results, a, qd), 0) << " | "
       << fixed(mean_of(results, a, best), 1) << " |\n";
  }
  const double best_ratio = mean_of(results, "map-elites", best) / mean_of(results, "ga", best);
  md << "\nMAP-Elites' best elite is " << fixed(100.0 * best_ratio, 1) << " % of the GA's best (mean over seeds).\n\n"
     << "Per seed: qd.csv. Chart: qd.svg.\n";
  fs::create_directories(out);
  soda::write_file_atomically(out / "qd.csv", results_csv(results));
  soda::write_file_atomically(out / "qd.svg", render_bar_chart(chart));
  soda::write_file_atomically(out / "qd.md", md.str());
  std::cout << md.str();
}

} // namespace

void add_bench_qd_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchQdOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "qd",
      "MAP-Elites against the GA at equal evaluations over several seeds: QD-score, coverage and\n"
      "best fitness, the GA's last population counted as an archive of the same grid. Writes\n"
      "qd.csv, qd.md and qd.svg (and the runs under qd-runs/).");
  cmd->add_option("--config", opt->config, "A MAP-Elites config")
      ->default_val("configs/map_elites.json")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--seeds", opt->seeds, "Seeds 1..N")->default_val(5)->check(CLI::Range(1, 1000));
  cmd->add_option("--iterations", opt->iterations, "MAP-Elites iterations (0 = the config's)")
      ->default_val(0)
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  cmd->callback([opt] {
    std::string command = "sodaevo bench qd --config " + opt->config + " --seeds " + std::to_string(opt->seeds);
    if (opt->iterations > 0) command += " --iterations " + std::to_string(opt->iterations);
    run_bench_qd(*opt, command);
  });
}

} // namespace sodaevo::app
