// `sodaevo bench accuracy` (work-precision, bench/accuracy_bench.hpp) and
// `sodaevo bench stress` (stability, bench/extreme_creatures.hpp): their options,
// then the benchmark and its files under results/bench/ (bench/accuracy_report.hpp:
// CSV, log-log SVG charts and a Markdown summary; bench/stress_report.hpp).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "app/commands.hpp"
#include "bench/accuracy_bench.hpp"
#include "bench/accuracy_report.hpp"
#include "bench/extreme_creatures.hpp"
#include "bench/stress_report.hpp"
#include "core/input_error.hpp"
#include "evolve/evaluators/parallel_for.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;

struct BenchAccuracyOptions {
  bool quick = false;
  std::string out = "results/bench";
  std::string models = "models";
  std::string champions = "models/champions";
  int walkers = 100;
  int replicas = 6;
  long long frames = 1000;
  long long walker_frames = 1000;
};

/// Every *.xml in `dir`, by file name (none if the folder does not exist).
std::vector<std::pair<std::string, std::string>> champions_in(const fs::path& dir) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!fs::is_directory(dir)) return out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".xml") out.emplace_back(e.path().stem().string(), e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void run_bench_accuracy(const BenchAccuracyOptions& opt, const std::string& command) {
  bench::AccuracyOptions ao;
  ao.quick = opt.quick;
  ao.walkers = opt.walkers;
  ao.replicas = opt.replicas;
  ao.classic_frames = opt.frames;
  ao.walker_frames = opt.walker_frames;
  for (const char* name : {"dainty_walker", "carefulslug", "monster_truck", "treader", "wodka_m1", "wheel", "turbine"}) {
    const fs::path p = fs::path(opt.models) / (std::string(name) + ".xml");
    if (!fs::exists(p)) {
      throw soda::InputError(p.string() + ": bundled creature not found (run from the project root or pass --models DIR)");
    }
    ao.classics.emplace_back(name, p.string());
  }
  ao.champions = champions_in(opt.champions);
  if (ao.champions.empty()) std::cerr << "bench accuracy: no champions in " << opt.champions << " (section left out)\n";
  ao.progress = [](const std::string& line) { std::cerr << "bench accuracy: " << line << std::endl; };
  const bench::AccuracyReport report = bench::run_accuracy_bench(ao);

  const bench::AccuracyFiles files = bench::write_accuracy_files(opt.out, report, command);
  std::cout << files.markdown;
  std::cerr << "bench accuracy: wrote";
  for (const auto& f : files.written) std::cerr << ' ' << (fs::path(opt.out) / f).string();
  std::cerr << '\n';
}

struct BenchStressOptions {
  long long creatures = 1'000'000;
  long long frames = 20;
  std::uint64_t seed = 1;
  int threads = 0;
  bool all_modes = false;
  std::string out = "results/bench";
};

void run_bench_stress(const BenchStressOptions& opt, const std::string& command) {
  bench::StressOptions so;
  so.seed = opt.seed;
  so.creatures = opt.creatures;
  so.frames = opt.frames;
  so.threads = resolve_thread_count(opt.threads);
  if (opt.all_modes) {
    so.steppings = {soda::Stepping{},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Euler, 4},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Verlet, 4},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 4},
                    {soda::PhysicsMode::Continuous, soda::Integrator::BackwardEuler, 1},
                    {soda::PhysicsMode::Continuous, soda::Integrator::ImplicitMidpoint, 1}};
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<bench::StressCounts> counts = bench::run_stress(so);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bench::StressFiles files = bench::write_stress_files(opt.out, counts, so, command, seconds);
  std::cout << files.markdown;
  if (files.escaped) throw soda::InputError("bench stress: a non-finite value escaped the divergence detector (see above)");
}

} // namespace

void add_bench_accuracy_commands(CLI::App& bench) {
  auto opt = std::make_shared<BenchAccuracyOptions>();
  CLI::App* acc = bench.add_subcommand(
      "accuracy",
      "Work-precision: run time against error for soda and the continuous mode's integrators\n"
      "at dt = 1 ... 1/64 frame, on analytic scenes (closed forms), the bundled classics and the\n"
      "GA's champions (expected distance over sine-jitter replicas vs RK4 at 128 sub-steps, with\n"
      "95 % intervals) and random walkers (Kendall tau of the ranking by expected distance).\n"
      "Writes accuracy.csv, accuracy_*.svg (log-log) and accuracy.md. Takes about 10 minutes.");
  acc->add_flag("--quick", opt->quick, "Small sweep (dt down to 1/8, 20 walkers, 3 replicas, short runs): a smoke test");
  acc->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  acc->add_option("--models", opt->models, "Directory with the bundled creatures")->default_val("models");
  acc->add_option("--champions", opt->champions, "Directory with the GA's champions (*.xml; none: left out)")
      ->default_val("models/champions");
  acc->add_option("--walkers", opt->walkers, "Random walkers ranked")->default_val(100)->check(CLI::Range(2, 100000));
  acc->add_option("--replicas", opt->replicas, "Sine-jitter replicas per creature and setting (expected distances)")
      ->default_val(6)
      ->check(CLI::Range(2, 1024));
  acc->add_option("--frames", opt->frames, "Scored frames of the classics and champions (after 100 settle frames)")
      ->default_val(1000)
      ->check(CLI::Range(1LL, 10'000'000LL));
  acc->add_option("--walker-frames", opt->walker_frames, "Scored frames of each random walker")
      ->default_val(1000)
      ->check(CLI::Range(1LL, 10'000'000LL));
  acc->callback([opt] {
    std::string command = "sodaevo bench accuracy";
    if (opt->quick) command += " --quick";
    if (opt->walkers != 100) command += " --walkers " + std::to_string(opt->walkers);
    if (opt->replicas != 6) command += " --replicas " + std::to_string(opt->replicas);
    if (opt->frames != 1000) command += " --frames " + std::to_string(opt->frames);
    if (opt->walker_frames != 1000) command += " --walker-frames " + std::to_string(opt->walker_frames);
    run_bench_accuracy(*opt, command);
  });

  auto sopt = std::make_shared<BenchStressOptions>();
  CLI::App* stress = bench.add_subcommand(
      "stress",
      "Stability: random creatures with extreme but legal parameters (springyness 0.5, gravity 4,\n"
      "hubs, zero/negative/huge rest lengths, coincident masses, masses outside the container,\n"
      "links listed twice), every frame watched by the divergence detector. Reports creatures\n"
      "tried and flagged; fails if a non-finite value escapes. Writes stress.csv and stress.md.");
  stress->add_option("--creatures", sopt->creatures, "Creatures to try")
      ->default_val(1000000)
      ->check(CLI::Range(1LL, 1'000'000'000LL));
  stress->add_option("--frames", sopt->frames, "Frames per creature")->default_val(20)->check(CLI::Range(1LL, 1'000'000LL));
  stress->add_option("--seed", sopt->seed, "Seed of the creatures")->default_val(1);
  stress->add_option("--threads", sopt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  stress->add_flag("--all-modes", sopt->all_modes, "Also run continuous euler, verlet and rk4 at 4 sub-steps, backward-euler and\nimplicit-midpoint at 1");
  stress->add_option("--out", sopt->out, "Output directory")->default_val("results/bench");
  stress->callback([sopt] {
    std::string command = "sodaevo bench stress --creatures " + std::to_string(sopt->creatures) + " --frames " +
                          std::to_string(sopt->frames);
    if (sopt->seed != 1) command += " --seed " + std::to_string(sopt->seed);
    if (sopt->all_modes) command += " --all-modes";
    run_bench_stress(*sopt, command);
  });
}

} // namespace sodaevo::app
