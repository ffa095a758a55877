// `sodaevo bench speed`: its options, then the speed benchmark (bench/speed_bench.hpp)
// and its files (bench/speed_report.hpp: CSV, SVG charts, a Markdown table) under
// results/bench/.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "bench/speed_bench.hpp"
#include "bench/speed_report.hpp"
#include "core/input_error.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;

struct BenchSpeedOptions {
  bool quick = false;
  std::string out = "results/bench";
  std::string models = "models";
  int threads = 0;
  std::vector<std::string> sections; ///< empty: all
  bool out_given = false;
  std::string ga_run = "results/bench/evolve-run-default";
  bool ga_run_given = false;
  std::string simd = "auto";
  bool cpu_time = false;
};

void run_bench_speed(const BenchSpeedOptions& opt, const std::string& command) {
  bench::SpeedOptions so;
  so.quick = opt.quick;
  so.threads = opt.threads;
  so.simd = opt.simd;
  so.cpu_time = opt.cpu_time;
  const bool all_sections = opt.sections.empty();
  auto wanted = [&](const char* name) {
    return all_sections || std::find(opt.sections.begin(), opt.sections.end(), name) != opt.sections.end();
  };
  so.creature_section = wanted("creature");
  so.size_section = wanted("size");
  so.population_section = wanted("population");
  so.ga_section = wanted("ga");
  // The GA section needs a saved run: the project's own (results/) by default. A
  // full run goes on without it where it is missing (a clone run elsewhere); asked
  // for by name or by --ga-run, it must be there.
  if (so.ga_section) {
    if (fs::exists(fs::path(opt.ga_run) / "config.json")) {
      so.ga_run = opt.ga_run;
    } else if (opt.ga_run_given || !all_sections) {
      throw soda::InputError(opt.ga_run + ": no saved run here (config.json missing); pass --ga-run RUN_DIR, a "
                             "directory `sodaevo evolve` wrote");
    } else {
      std::cerr << "bench speed: no saved run at " << opt.ga_run
                << ": the GA section is skipped (pass --ga-run RUN_DIR)\n";
    }
  }
  for (const char* name : {"dainty_walker", "carefulslug", "monster_truck"}) {
    if (!so.creature_section && !so.population_section) break; // only these step the bundled creatures
    const fs::path p = fs::path(opt.models) / (std::string(name) + ".xml");
    if (!fs::exists(p)) {
      throw soda::InputError(p.string() +
                             ": bundled creature not found (run from the project root or pass --models DIR)");
    }
    so.creatures.emplace_back(name, p.string());
  }
  so.progress = [](const std::string& line) { std::cerr << "bench speed: " << line << std::endl; };
  const bench::SpeedReport report = bench::run_speed_bench(so);
  const std::string table = bench::speed_markdown(report, command);
  std::cout << table;
  // A run of some sections does not overwrite the full results unless asked to.
  if (!all_sections && !opt.out_given) {
    std::cerr << "bench speed: some sections only: nothing written (pass --out DIR to write the files)\n";
    return;
  }
  const std::vector<std::string> written = bench::write_speed_files(opt.out, report, so, table);
  std::cerr << "bench speed: wrote " << (fs::path(opt.out) / written.front()).string();
  for (std::size_t i = 1; i < written.size(); ++i) std::cerr << ", " << written[i];
  std::cerr << "\n";
}

} // namespace

void add_bench_command(CLI::App& app) {
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks (results under results/bench/)");
  bench->require_subcommand(1);
  auto opt = std::make_shared<BenchSpeedOptions>();
  CLI::App* speed = bench->add_subcommand(
      "speed",
      "Frames and link updates per second: seed paper baseline, plain loop, reference and fast step\n"
      "on the bundled creatures, a size sweep (10..100,000 links) and population throughput on\n"
      "1 and all threads, and the GA's own creatures from a saved run. Writes speed.csv, speed.svg,\n"
      "speed_creatures.svg, speed_rounds.csv (every timed run of the population section) and speed.md.");
  speed->add_flag("--quick", opt->quick, "Short runs (a few seconds) for a smoke test");
  CLI::Option* out = speed->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  speed->add_option("--models", opt->models, "Directory with the bundled creatures")->default_val("models");
  speed->add_option("--threads", opt->threads, "Threads for the population run (0 = all cores)")
      ->default_val(0)
      ->check(CLI::Range(0, 1024));
  speed
      ->add_option("--sections", opt->sections,
                   "Only these sections (comma-separated): creature, size, population, ga. A partial run prints its "
                   "table and writes files only with an explicit --out")
      ->delimiter(',')
      ->check(CLI::IsMember({"creature", "size", "population", "ga"}));
  CLI::Option* ga_run =
      speed
          ->add_option("--ga-run", opt->ga_run,
                       "A run directory of `sodaevo evolve` whose saved generations the ga section steps (every "
                       "creature, as the GA evaluates it)")
          ->default_val(opt->ga_run);
  speed
      ->add_option("--simd", opt->simd,
                   "The SIMD level every engine runs (a level the CPU lacks: its best); the environment variable "
                   "SODAEVO_SIMD does the same for every command")
      ->default_val(opt->simd)
      ->check(CLI::IsMember({"auto", "sse2", "avx2", "avx512"}));
  speed->add_flag("--cpu-time", opt->cpu_time,
                  "Time the creature, size and ga sections by the thread's CPU time, not the wall clock: on a "
                  "machine shared with other work, the time slices others take are not counted");
  add_bench_accuracy_commands(*bench);
  speed->callback([opt, out, ga_run] {
    std::string command = "sodaevo bench speed";
    if (opt->quick) command += " --quick";
    if (opt->threads > 0) command += " --threads " + std::to_string(opt->threads);
    if (opt->simd != "auto") command += " --simd " + opt->simd;
    if (opt->cpu_time) command += " --cpu-time";
    if (!opt->sections.empty()) {
      command += " --sections ";
      for (std::size_t i = 0; i < opt->sections.size(); ++i) command += (i ? "," : "") + opt->sections[i];
    }
    opt->out_given = out->count() > 0;
    opt->ga_run_given = ga_run->count() > 0;
    run_bench_speed(*opt, command);
  });
  add_bench_evolve_command(*bench);
  add_bench_transfer_command(*bench);
  add_bench_qd_command(*bench);
  add_bench_races_command(*bench);
  add_bench_stability_command(*bench);
}

} // namespace sodaevo::app
