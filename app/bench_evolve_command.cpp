// `sodaevo bench evolve`: the evolution benchmark (bench/evolve_bench.hpp): GA vs
// random search vs hill climber at equal evaluations over several seeds, then a
// full run of the config against the Dainty Walker. Writes evolve.csv,
// evolve.svg and evolve.md under results/bench/.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.hpp"
#include "app/fixed_text.hpp"
#include "app/svg_chart.hpp"
#include "bench/evolve_bench.hpp"
#include "core/input_error.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/evolution_run.hpp"
#include "evolve/run_reader.hpp"
#include "evolve/run_roles.hpp"
#include "evolve/run_store.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;

struct BenchEvolveOptions {
  std::string config = "configs/default.json";
  std::string classic = "models/dainty_walker.xml";
  int generations = 30;
  int seeds = 5;
  int threads = 0;
  bool skip_full_run = false;
  std::string out = "results/bench";
};

struct FullRun {
  bool done = false;
  double wall_seconds = 0.0;
  long long evaluations = 0;
  int generations = 0;
  double best_fitness = 0.0;
  std::string best_id;
  std::string run_dir;
};

const char* method_label(const std::string& m) {
  if (m == "ga") return "genetic algorithm";
  if (m == "random") return "random search";
  return "hill climber (1+1)";
}

std::string comparison_csv(const bench::SearchComparison& c) {
  std::ostringstream o;
  o << "method,seed,evaluations,best_fitness_at_common_budget,best_px_per_frame\n";
  for (const bench::SearchRun& r : c.runs) {
    o << r.method << ',' << r.seed << ',' << c.evaluations << ',' << fixed(bench::best_after(r, c.evaluations), 6)
      << ',' << fixed(r.best_px_per_frame, 6) << '\n';
  }
  return o.str();
}

std::string comparison_svg(const bench::SearchComparison& c, long long frames) {
  LineChart chart;
  chart.title = "Best distance walked vs evaluations (median over seeds)";
  chart.x_axis = {"evaluations", false};
  chart.y_axis = {"best fitness: px per frame", false};
  for (const char* m : {"ga", "random", "hill"}) {
    LineSeries s;
    s.name = method_label(m);
    s.markers = false;
    const long long step = std::max<long long>(1, c.evaluations / 60);
    for (long long e = step; e <= c.evaluations; e += step) {
      s.x.push_back(static_cast<double>(e));
      s.y.push_back(bench::median_best(c, m, e) / static_cast<double>(frames));
    }
    chart.series.push_back(std::move(s));
  }
  return render_line_chart(chart);
}

void run_bench_evolve(const BenchEvolveOptions& opt, const std::string& command) {
  const RunConfig config = read_run_config(opt.config);
  const soda::ModelDef classic = soda::read_model_file(opt.classic).def;
  auto say = [](const std::string& s) { std::cerr << "bench evolve: " << s << std::endl; };

  bench::SearchComparisonOptions so;
  so.config = config;
  so.seed_creatures = load_seed_creatures(config);
  so.seeds.clear();
  for (int s = 1; s <= opt.seeds; ++s) so.seeds.push_back(static_cast<std::uint64_t>(s));
  so.generations = opt.generations;
  so.threads = opt.threads;
  so.progress = say;
  const auto t0 = std::chrono::steady_clock::now();
  const bench::SearchComparison comparison = bench::compare_search_methods(so);
  const double comparison_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const bench::ClassicSpeed dw = bench::classic_speed(classic, config);
  const double frames = static_cast<double>(config.fitness.frames);

  FullRun full;
  if (!opt.skip_full_run) {
    full.run_dir = (fs::path(opt.out) / ("evolve-run-" + config.name)).string();
    RunStore store = RunStore::create(full.run_dir, config, true, command);
    ThreadEvaluator evaluator(opt.threads);
    EvolutionOptions eo;
    eo.on_generation = [&](const Progress& p) {
      if (p.generation % 10 == 0 || p.generation + 1 == p.generations) {
        say("full run: generation " + std::to_string(p.generation) + "/" + std::to_string(p.generations) + ", best " +
            fixed(p.stats.best / frames, 3) + " px/frame");
      }
    };
    const auto r0 = std::chrono::steady_clock::now();
    const EvolutionOutcome outcome = run_evolution(store, evaluator, eo);
    full.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    full.done = true;
    full.evaluations = outcome.evaluations;
    full.generations = outcome.last_generation + 1;
    full.best_fitness = outcome.best_fitness;
    full.best_id = outcome.best_id;
    // The champion as SodaConstructor XML next to the figures (the run folder
    // itself is large and not kept in the repository).
    for (const Individual& champion : best_individuals(full.run_dir, 1)) {
      soda::write_model_file(fs::path(opt.out) / "evolve_champion.xml",
                             roles_of(config).problem->export_form(champion.creature, champion.id, champion.evaluation));
    }
  }

  std::ostringstream md;
  md << "Measured with `" << command << "` (" << opt.seeds << " seeds; fitness: " << config.fitness.frames
     << " frames after " << config.fitness.settle_frames << " settle frames, "
     << (config.fitness.scaling == FitnessScaling::Sodarace ? "Sodarace scaling" : "no scaling") << ").\n\n";
  md << "Search methods at equal evaluations (" << comparison.evaluations << " each = " << opt.generations
     << " GA generations of " << config.population.size << "), best fitness in px/frame:\n\n";
  md << "| method | median best | min | max |\n|---|---:|---:|---:|\n";
  for (const char* m : {"ga", "random", "hill"}) {
    double lo = INFINITY, hi = -INFINITY;
    for (const bench::SearchRun& r : comparison.runs) {
      if (r.method != m) continue;
      const double b = bench::best_after(r, comparison.evaluations);
      lo = std::min(lo, b);
      hi = std::max(hi, b);
    }
    md << "| " << method_label(m) << " | " << fixed(bench::median_best(comparison, m, comparison.evaluations) / frames, 3)
       << " | " << fixed(lo / frames, 3) << " | " << fixed(hi / frames, 3) << " |\n";
  }
  const double ga = bench::median_best(comparison, "ga", comparison.evaluations);
  const double rs = bench::median_best(comparison, "random", comparison.evaluations);
  const double hc = bench::median_best(comparison, "hill", comparison.evaluations);
  md << "\nGA / random search: " << fixed(ga / rs, 2) << "x; GA / hill climber: " << fixed(ga / hc, 2)
     << "x (medians). Comparison wall time " << fixed(comparison_seconds, 1) << " s.\n\n";
  md << "Dainty Walker under the same fitness settings: " << fixed(dw.forward_px_per_frame, 3)
     << " px/frame with its wave as written, " << fixed(dw.reversed_px_per_frame, 3)
     << " reversed; best in the configured direction " << fixed(dw.best_fitness_px_per_frame, 3) << " px/frame.\n";
  if (full.done) {
    const double champion = full.best_fitness / frames;
    md << "\nFull run of `" << opt.config << "` (" << full.generations << " generations, " << full.evaluations
       << " evaluations, " << (opt.threads > 0 ? std::to_string(opt.threads) : std::string("all")) << " threads): "
       << fixed(full.wall_seconds, 1) << " s, champion " << full.best_id << " at " << fixed(champion, 3)
       << " px/frame = " << fixed(champion / dw.best_fitness_px_per_frame, 2)
       << "x the Dainty Walker's best. Champion: `evolve_champion.xml`; run folder (not committed): `" << full.run_dir << "`.\n";
  }

  fs::create_directories(opt.out);
  const fs::path out(opt.out);
  soda::write_file_atomically(out / "evolve.csv", comparison_csv(comparison));
  soda::write_file_atomically(out / "evolve.svg", comparison_svg(comparison, config.fitness.frames));
  soda::write_file_atomically(out / "evolve.md", md.str());
  std::cout << md.str();
  say("wrote " + (out / "evolve.csv").string() + ", evolve.svg, evolve.md");
}

} // namespace

void add_bench_evolve_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchEvolveOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "evolve",
      "Is the GA worth it? GA vs random search vs a (1+1) hill climber at equal evaluations,\n"
      "from the same initial creatures, over several seeds (median best distance); then a full\n"
      "run of the config, its champion's speed against the Dainty Walker's under the same fitness\n"
      "settings. Writes evolve.csv, evolve.svg and evolve.md (and the full run's folder).");
  cmd->add_option("--config", opt->config, "Config whose GA, world and fitness are compared")
      ->default_val("configs/default.json")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--classic", opt->classic, "Classic creature to compare the champion with")
      ->default_val("models/dainty_walker.xml")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--generations", opt->generations,
                  "GA generations in the comparison; the other methods get the same evaluation count")
      ->default_val(30)
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--seeds", opt->seeds, "Seeds per method (1..N)")->default_val(5)->check(CLI::Range(1, 1000));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->add_flag("--skip-full-run", opt->skip_full_run, "Only the comparison, not the full run of the config");
  cmd->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  cmd->callback([opt] {
    std::string command = "sodaevo bench evolve --config " + opt->config + " --generations " +
                          std::to_string(opt->generations) + " --seeds " + std::to_string(opt->seeds);
    if (opt->threads > 0) command += " --threads " + std::to_string(opt->threads);
    if (opt->skip_full_run) command += " --skip-full-run";
    run_bench_evolve(*opt, command);
  });
}

} // namespace sodaevo::app
