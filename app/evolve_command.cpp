#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "app/run_report.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/evolution_run.hpp"
#include "evolve/run_config.hpp"
#include "evolve/run_store.hpp"

namespace sodaevo::app {

namespace {

struct EvolveOptions {
  std::string config;
  std::string out;
  std::string resume;
  int threads = 0;
  bool force = false;
  bool quiet = false;
};

std::atomic<bool> g_stop_requested{false};

/// report.html in the run folder is refreshed after every this many generations
/// (a few trials each time: cheap next to a generation) and at the end.
constexpr int kReportEveryGenerations = 5;

extern "C" void on_interrupt(int) {
  // First Ctrl-C: finish the generation and save. Second: stop at once.
  if (g_stop_requested.exchange(true)) std::_Exit(130);
}

std::string timestamp() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
  return buf;
}

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "?";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, s / 60 % 60);
  else if (s >= 60) std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%lds", s);
  return buf;
}

void run_evolve(const EvolveOptions& opt, const std::string& command_line) {
  if (opt.resume.empty() == opt.config.empty()) {
    throw soda::InputError("give either a CONFIG.json to start a run or --resume RUN_FOLDER to continue one");
  }
  std::optional<RunStore> store;
  if (!opt.resume.empty()) {
    store.emplace(RunStore::open(opt.resume));
  } else {
    const RunConfig config = read_run_config(opt.config);
    const std::string dir = opt.out.empty() ? "results/" + config.name + "-" + timestamp() : opt.out;
    store.emplace(RunStore::create(dir, config, opt.force, command_line));
  }
  ThreadEvaluator evaluator(opt.threads);
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  if (!opt.quiet) {
    std::cerr << (opt.resume.empty() ? "evolving" : "resuming") << " '" << store->config().name << "' into "
              << store->dir().string() << " on " << evaluator.threads() << " thread(s); Ctrl-C stops after the current generation\n";
  }

  EvolutionOptions options;
  options.stop_requested = &g_stop_requested;
  auto refresh_report = [&] {
    try {
      write_run_report(store->dir(), default_report_path(store->dir()));
    } catch (const std::exception& e) {
      std::cerr << "\nsodaevo: warning: report not written: " << e.what() << '\n';
    }
  };
  options.on_generation = [&](const Progress& p) {
    if (p.generation % kReportEveryGenerations == 0) refresh_report();
    if (opt.quiet) return;
    const double per_generation = p.wall_seconds / (p.generation + 1);
    const double left = per_generation * (p.generations - p.generation - 1);
    char line[256];
    std::snprintf(line, sizeof line, "gen %d/%d  best %.2f  mean %.2f  invalid %d  %.0f evals/s  elapsed %s  left ~%s",
                  p.generation, p.generations - 1, p.stats.best, p.stats.mean, p.stats.invalid + p.stats.diverged,
                  p.evaluations_per_second, format_duration(p.wall_seconds).c_str(), format_duration(left).c_str());
    if (tty) std::cerr << "\r\033[K" << line << std::flush;
    else std::cerr << line << '\n';
  };
  std::signal(SIGINT, on_interrupt);
  const EvolutionOutcome outcome = run_evolution(*store, evaluator, options);
  std::signal(SIGINT, SIG_DFL);
  refresh_report();
  if (!opt.quiet) {
    if (tty) std::cerr << '\n';
    std::cerr << "stopped: " << outcome.stopped_because << " after generation " << outcome.last_generation << " ("
              << outcome.evaluations << " evaluations)\n";
  }
  std::cout << "run folder   " << store->dir().string() << "\n"
            << "best         " << outcome.best_id << "  fitness " << soda::format_double_plain(outcome.best_fitness)
            << " px in " << store->config().fitness.frames << " frames ("
            << soda::format_double_plain(outcome.best_fitness / static_cast<double>(store->config().fitness.frames))
            << " px/frame)\n"
            << "report       " << default_report_path(store->dir()).string() << "\n"
            << "export with  sodaevo export " << store->dir().string() << " --best 5 --out DIR\n";
}

} // namespace

void add_evolve_command(CLI::App& app) {
  auto opt = std::make_shared<EvolveOptions>();
  CLI::App* cmd = app.add_subcommand(
      "evolve",
      "Evolve walkers with a genetic algorithm from a JSON config (see configs/README.md).\n"
      "Writes a run folder: resolved config, generations.csv, timing.csv, the best creature\n"
      "of every generation as SodaConstructor XML, saved generations, checkpoints and report.html\n"
      "(see `sodaevo report`, refreshed every few generations).");
  cmd->add_option("config", opt->config, "Run config (.json)")->check(CLI::ExistingFile);
  cmd->add_option("--out", opt->out, "Run folder (default results/<config name>-<timestamp>)");
  cmd->add_option("--resume", opt->resume, "Continue the interrupted run in this folder from its last checkpoint")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--threads", opt->threads, "Evaluation threads (0 = all cores); results do not depend on it")
      ->default_val(0)
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--force", opt->force, "Replace an existing run folder");
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->callback([opt] {
    std::string command_line = "sodaevo evolve";
    if (!opt->config.empty()) command_line += " " + opt->config;
    if (!opt->out.empty()) command_line += " --out " + opt->out;
    if (!opt->resume.empty()) command_line += " --resume " + opt->resume;
    command_line += " --threads " + std::to_string(opt->threads);
    run_evolve(*opt, command_line);
  });
}

} // namespace sodaevo::app
