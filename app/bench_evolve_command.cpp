// `sodaevo bench evolve`: its options, then the evolution benchmark
// (bench/evolve_bench.hpp): GA vs random search vs hill climber at equal
// evaluations over several seeds, then a full run of the config against the Dainty
// Walker (bench/evolve_report.hpp, which writes evolve.csv, evolve.svg and evolve.md
// under results/bench/).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "bench/evolve_bench.hpp"
#include "bench/evolve_report.hpp"
#include "evolve/runs/evolution_run.hpp"
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

  bench::EvolveReport report;
  report.command = command;
  report.config_path = opt.config;
  report.config = config;
  report.seeds = opt.seeds;
  report.generations = opt.generations;
  report.threads = opt.threads;
  report.comparison = comparison;
  report.comparison_seconds = comparison_seconds;
  report.classic = bench::classic_speed(classic, config);
  if (!opt.skip_full_run) report.full = bench::run_full_evolution(config, opt.out, opt.threads, command, say);
  std::cout << bench::write_evolve_files(opt.out, report);
  const fs::path out(opt.out);
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
