#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <csignal>
#include <optional>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "app/evolve_map_elites.hpp"
#include "app/run_report.hpp"
#include "charts/fixed_text.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "core/sine_identity.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/evaluators/mpi_launch.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_sine.hpp"
#include "evolve/store/run_store.hpp"
#if SODAEVO_HAS_MPI
#include "evolve/mpi/mpi_evaluator.hpp"
#endif
#include "app/mpi_context.hpp"

namespace sodaevo::app {

using charts::fixed;

#if SODAEVO_HAS_MPI
namespace {
MpiSession* g_mpi_session = nullptr;
}
void set_current_mpi_session(MpiSession* session) { g_mpi_session = session; }
MpiSession* current_mpi_session() { return g_mpi_session; }
#endif

namespace {

struct EvolveOptions {
  std::string config;
  std::string out;
  std::string resume;
  int threads = 0;
  bool force = false;
  bool quiet = false;
  bool resume_other_sine = false;
};

std::atomic<bool> g_stop_requested{false};

/// report.html in the run folder is refreshed after every this many generations
/// (a few trials each time: cheap next to a generation) and at the end.
constexpr int kReportEveryGenerations = 5;

extern "C" void on_interrupt(int) {
  // First Ctrl-C: finish the generation and save. Second: stop at once.
  if (g_stop_requested.exchange(true)) std::_Exit(130);
}

extern "C" void on_polite_stop(int) { g_stop_requested = true; }

// What to say when the process is terminated (mpirun sends SIGTERM to every rank
// when one dies or the job is cancelled). Filled before the run starts, so the
// handler only calls write(2) and _exit(2).
char g_terminated_message[1024] = "";

extern "C" void on_terminate(int) {
  const std::size_t length = std::strlen(g_terminated_message);
  if (length > 0 && ::write(STDERR_FILENO, g_terminated_message, length) < 0) {}
  std::_Exit(143);
}

void prepare_terminated_message(const std::string& dir) {
  const std::string text = "\nsodaevo: terminated by a signal (under mpirun: a rank died or the job was cancelled).\n"
                           "The run folder is intact at its last checkpoint; continue with (any number of ranks):\n"
                           "  sodaevo evolve --resume " + dir + "\n";
  std::snprintf(g_terminated_message, sizeof g_terminated_message, "%s", text.c_str());
}

/// The stop signals (Ctrl-C, SIGUSR1: finish the step and save; SIGTERM: say how
/// to resume and exit) handled while a run is in this scope, whichever algorithm
/// runs, and the defaults restored when it is left, by a return or an exception.
class StopSignals {
 public:
  explicit StopSignals(const std::string& dir) {
    prepare_terminated_message(dir);
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGUSR1, on_polite_stop);
    std::signal(SIGTERM, on_terminate);
  }
  ~StopSignals() {
    std::signal(SIGTERM, SIG_DFL);
    std::signal(SIGUSR1, SIG_DFL);
    std::signal(SIGINT, SIG_DFL);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

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

/// A run made with another sine is not continued silently (a run never mixes
/// sines unrecorded): refused, or with --resume-other-sine continued from its
/// checkpoint scored again with this engine's sine, the change recorded in
/// manifest.json. Returns whether the checkpoint is to be scored again.
bool accept_resume_sine(const RunStore& store, const EvolveOptions& opt) {
  const bool map_elites = store.config().algorithm == AlgorithmKind::MapElites;
  const std::optional<ResumePoint> p = resume_point(store.dir(), map_elites);
  if (!p || p->sine == soda::kEngineSine) return false;
  const std::string dir = store.dir().string();
  const std::string note = other_sine_note("this run was made", p->sine, p->recorded) + " (read from " + p->file + ")";
  if (map_elites) {
    throw soda::InputError(dir + ": not resumed: " + note +
                           ".\nA MAP-Elites archive cannot change sine part way (its elites hold the old sine's "
                           "estimates, their cells its descriptors), so --resume-other-sine does not apply. Start a "
                           "new run from the same config:\n  sodaevo evolve " + (store.dir() / "config.json").string() +
                           " --out NEW_FOLDER");
  }
  const std::string g = std::to_string(p->generation);
  if (!opt.resume_other_sine) {
    throw soda::InputError(dir + ": not resumed: " + note +
                           ".\nContinuing it here would mix two sines in one run. Either continue it with this "
                           "engine's sine (generation " + g + ", its checkpoint, is scored again and every generation "
                           "from " + g + " on is made with " + sine_description(soda::kEngineSine) +
                           "; manifest.json records the change):\n  sodaevo evolve --resume " + dir +
                           " --resume-other-sine\nor start a new run from the same config:\n  sodaevo evolve " +
                           (store.dir() / "config.json").string() + " --out NEW_FOLDER");
  }
  record_sine_change(store.dir(), p->generation, p->sine);
  std::cerr << "sodaevo: " << note << ".\nContinuing with this engine's sine (--resume-other-sine): generation " << g
            << " is scored again, and it and every later generation are made with "
            << sine_description(soda::kEngineSine) << "; recorded in " << (store.dir() / "manifest.json").string()
            << " (sine_changes).\n";
  return true;
}

void run_evolve(const EvolveOptions& opt, const std::string& command_line) {
  if (!mpi_support_built() && launcher_rank_count() > 1) {
    throw soda::InputError("this sodaevo was built without MPI support, so it cannot share one run between the " +
                           std::to_string(launcher_rank_count()) +
                           " processes the MPI launcher started (each would run the whole evolution into the "
                           "same folder). Run it without mpirun, or rebuild with MPI (install libopenmpi-dev; "
                           "CMake option SODAEVO_MPI). `sodaevo --version` says whether MPI is built in.");
  }
  if (opt.resume.empty() == opt.config.empty()) {
    throw soda::InputError("give either a CONFIG.json to start a run or --resume RUN_FOLDER to continue one");
  }
  if (opt.resume_other_sine && opt.resume.empty()) {
    throw soda::InputError("--resume-other-sine continues a run made with another sine: give it with --resume RUN_FOLDER");
  }
  std::optional<RunStore> store;
  bool rescore_checkpoint = false;
  if (!opt.resume.empty()) {
    store.emplace(RunStore::open(opt.resume));
    rescore_checkpoint = accept_resume_sine(*store, opt);
  } else {
    const RunConfig config = read_run_config(opt.config);
    const std::string dir = opt.out.empty() ? "results/" + config.name + "-" + timestamp() : opt.out;
    store.emplace(start_run(config, opt.config, dir, opt.force, command_line));
  }
  std::unique_ptr<Evaluator> evaluator;
  std::string where;
#if SODAEVO_HAS_MPI
  MpiEvaluator* mpi_evaluator = nullptr;
  if (MpiSession* session = current_mpi_session()) {
    auto e = std::make_unique<MpiEvaluator>(*session, opt.threads);
    mpi_evaluator = e.get();
    where = std::to_string(session->size()) + " MPI rank(s), " + std::to_string(e->local_threads()) +
            " thread(s) on rank 0; kill -USR1 on mpirun";
    evaluator = std::move(e);
  }
#endif
  if (!evaluator) {
    auto e = std::make_unique<ThreadEvaluator>(opt.threads);
    where = std::to_string(e->threads()) + " thread(s); Ctrl-C";
    evaluator = std::move(e);
  }
  // Installed once, for either algorithm; the defaults are back once its loop ends.
  std::optional<StopSignals> signals(std::in_place, store->dir().string());
  if (store->config().algorithm == AlgorithmKind::MapElites) {
    if (!opt.quiet) {
      std::cerr << (opt.resume.empty() ? "evolving" : "resuming") << " '" << store->config().name
                << "' (MAP-Elites) into " << store->dir().string() << " on " << where
                << " stops after the current iteration\n";
    }
    try {
      evolve_map_elites(*store, *evaluator, opt.threads, opt.quiet, &g_stop_requested);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(e.what()) + "\nThe run stopped; the run folder is intact at its last "
                               "checkpoint. Continue with:\n  sodaevo evolve --resume " + store->dir().string());
    }
    return;
  }
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  if (!opt.quiet) {
    std::cerr << (opt.resume.empty() ? "evolving" : "resuming") << " '" << store->config().name << "' into "
              << store->dir().string() << " on " << where << " stops after the current generation\n";
  }

  EvolutionOptions options;
  options.stop_requested = &g_stop_requested;
  options.rescore_checkpoint = rescore_checkpoint;
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
    // No creature scored in this generation: no best or mean (the log holds no infinity).
    auto stat = [](double v) { return std::isfinite(v) ? fixed(v, 2) : std::string("-"); };
    // Counted from 1 as the page and the report count ("gen 10/10" is the last); the
    // ids (g9-1) and files (gen_0009.xml) number generations from 0.
    std::snprintf(line, sizeof line, "gen %d/%d  best %s  mean %s  invalid %d  %.0f evals/s  elapsed %s  left ~%s",
                  p.generation + 1, p.generations, stat(p.stats.best).c_str(), stat(p.stats.mean).c_str(),
                  p.stats.invalid + p.stats.diverged,
                  p.evaluations_per_second, format_duration(p.wall_seconds).c_str(), format_duration(left).c_str());
    if (tty) std::cerr << "\r\033[K" << line << std::flush;
    else std::cerr << line << '\n';
  };
  EvolutionOutcome outcome;
  try {
    outcome = run_evolution(*store, *evaluator, options);
  } catch (const std::exception& e) {
    // Nothing of the failed generation was recorded: every file is still the one
    // written at or before the last checkpoint (or a log row --resume drops).
    if (tty && !opt.quiet) std::cerr << '\n';
    throw std::runtime_error(std::string(e.what()) + "\nThe run stopped; the run folder is intact at its last checkpoint. Continue with:\n  sodaevo evolve --resume " +
                             store->dir().string());
  }
  signals.reset();
  // The best creatures again on fresh replicas: claimed against checked, for the
  // report (RUN/champions.json).
  std::vector<ReplicaCheck> checks;
  if (std::isfinite(outcome.best_fitness)) {
    try {
      checks = write_run_champions(store->dir(), kRunChampionsChecked, kRunChampionReplicas, opt.threads);
    } catch (const std::exception& e) {
      std::cerr << "\nsodaevo: warning: champions not checked: " << e.what() << '\n';
    }
  }
  refresh_report();
  if (!opt.quiet) {
    if (tty) std::cerr << '\n';
    std::cerr << "stopped: " << stop_reason_name(outcome.stopped_because) << " after generation " << outcome.last_generation + 1 << " ("
              << outcome.evaluations << " evaluations)\n";
#if SODAEVO_HAS_MPI
    if (mpi_evaluator) {
      const MpiTraffic& t = mpi_evaluator->traffic();
      const double farmed = static_cast<double>(std::max<long long>(1, t.creatures_farmed));
      char line[256];
      std::snprintf(line, sizeof line,
                    "MPI: %lld creatures evaluated on rank 0, %lld on other ranks in %lld chunks; "
                    "%.0f bytes per creature sent, %.0f bytes per creature returned\n",
                    t.creatures_local, t.creatures_farmed, t.work_messages, static_cast<double>(t.bytes_sent) / farmed,
                    static_cast<double>(t.bytes_received) / farmed);
      std::cerr << line;
    }
#endif
  }
  std::cout << "run folder   " << store->dir().string() << "\n";
  const RunConfig& config = store->config();
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  // What the best's fitness stands on: the statistic of its replicas (a single
  // rollout is one draw, not the creature's walk).
  const auto it = std::find_if(checks.begin(), checks.end(), [&](const ReplicaCheck& c) { return c.id == outcome.best_id; });
  std::string basis;
  if (it != checks.end() && it->selection.rollouts > 1) {
    basis = " (" + statistic_name(config.fitness.statistic) + " of " + std::to_string(it->selection.rollouts) +
            " replicas, sd " + fixed(it->selection.sd, 2) + ")";
  }
  if (std::isfinite(outcome.best_fitness)) {
    std::cout << "champion     " << outcome.best_id << " (best of the last generation)  fitness "
              << soda::format_double_plain(outcome.best_fitness) << basis;
    switch (config.fitness.kind) { // no default: a new kind says what its best did
      case FitnessKind::Walk:
        std::cout << " px in " << config.fitness.frames << " frames ("
                  << soda::format_double_plain(outcome.best_fitness / static_cast<double>(config.fitness.frames))
                  << " px/frame)\n";
        break;
      case FitnessKind::Race:
        std::cout << " (races in " << soda::format_double_plain(-outcome.best_fitness) << " frames)\n";
        break;
    }
  } else {
    std::cout << "champion     none: no creature could be scored (the reasons are in the saved generations)\n";
  }
  if (it != checks.end()) { // rounded for reading; champions.json keeps every digit
    std::cout << "             " << check_comment(*it, score.unit, score.digits) << "\n";
  }
  std::cout << "report       " << default_report_path(store->dir()).string() << "\n"
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
      "(see `sodaevo report`, refreshed every few generations). manifest.json records the engine's\n"
      "muscle sine: --resume refuses a run made with another (see --resume-other-sine).\n"
      "On a cluster: mpirun -np N sodaevo evolve CONFIG runs the algorithm on rank 0 and\n"
      "evaluates on every rank, with results identical to one process (docs/cluster.md).\n"
      "This build: " + mpi_support_summary() + ".");
  cmd->add_option("config", opt->config, "Run config (.json)")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", opt->out, "Run folder (default results/<config name>-<timestamp>)");
  cmd->add_option("--resume", opt->resume, "Continue the interrupted run in this folder from its last checkpoint")
      ->check(non_empty_path())
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("--resume-other-sine", opt->resume_other_sine,
                "With --resume: continue a run made with another muscle sine (runs made before " +
                    std::string(soda::kGlibcSineUntil) + " used\n"
                "glibc's sin; this engine computes Java's Math.sin). Without it such a resume is refused, as\n"
                "trajectories and fitnesses differ between sines and a run must not mix them. With it, the\n"
                "checkpoint's generation is scored again with this engine's sine and every generation from\n"
                "there on is made with it; manifest.json records the change (sine_changes), and replay and\n"
                "report name the sine of each generation. Not for MAP-Elites runs (start a new run).");
  cmd->add_option("--threads", opt->threads, "Evaluation threads per process (0 = all cores; under MPI, the node's cores shared\n"
                  "between its ranks); results do not depend on it")
      ->default_val(0)
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--force", opt->force, "Replace an existing run folder");
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->callback([opt] {
    std::string command_line = "sodaevo evolve";
    if (!opt->config.empty()) command_line += " " + opt->config;
    if (!opt->out.empty()) command_line += " --out " + opt->out;
    if (!opt->resume.empty()) command_line += " --resume " + opt->resume;
    if (opt->resume_other_sine) command_line += " --resume-other-sine";
    command_line += " --threads " + std::to_string(opt->threads);
    run_evolve(*opt, command_line);
  });
}

} // namespace sodaevo::app
