#include "app/evolve_map_elites.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "app/archive_report.hpp"
#include "charts/fixed_text.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/runs/map_elites_run.hpp"

namespace sodaevo::app {

using charts::fixed;

namespace {

constexpr int kReportEveryIterations = 20;

} // namespace

void evolve_map_elites(const RunStore& store, Evaluator& evaluator, int threads, bool quiet,
                       const std::atomic<bool>* stop) {
  const RunConfig& config = store.config();
  const MapElitesConfig& me = config.map_elites;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  auto refresh_report = [&] {
    try {
      write_archive_report(store.dir(), default_archive_report_path(store.dir()));
    } catch (const std::exception& e) {
      std::cerr << "\nsodaevo: warning: archive report not written: " << e.what() << '\n';
    }
  };
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  const auto shown = [&score](double fitness) { return fixed(score.shown(fitness), 2); };
  const std::string unit_text = std::string(" ") + score.unit;
  const char* unit = unit_text.c_str();
  MapElitesOptions options;
  options.stop_requested = stop;
  options.on_iteration = [&](const MapElitesProgress& p) {
    if (quiet) return;
    char line[256];
    std::snprintf(line, sizeof line,
                  "iteration %d/%d  %lld evaluations (%lld replicas)  filled %zu of %zu (%.1f %%)  QD-score %s  best %s%s",
                  p.iteration, p.iterations, p.evaluations, p.rollouts, p.metrics.filled, p.metrics.cells,
                  100.0 * p.metrics.coverage, fixed(p.metrics.qd_score, 0).c_str(), shown(p.metrics.best).c_str(), unit);
    if (tty) std::cerr << "\r\033[K" << line << std::flush;
    else if (p.iteration % kReportEveryIterations == 0 || p.iteration == p.iterations) std::cerr << line << '\n';
  };
  const MapElitesOutcome outcome = run_map_elites(store.dir(), config, me, evaluator, options);
  // The corrected archive: every elite again on fresh replicas (RUN/archive_checked.json).
  std::optional<CheckedArchive> checked;
  if (me.check_replicas > 0 && outcome.metrics.filled > 0) {
    if (!quiet) {
      std::cerr << (tty ? "\n" : "") << "checking " << outcome.metrics.filled << " elites on " << me.check_replicas
                << " fresh replicas each\n";
    }
    try {
      checked = write_checked_archive(store.dir(), threads);
    } catch (const std::exception& e) {
      std::cerr << "\nsodaevo: warning: archive not checked: " << e.what() << '\n';
    }
  }
  refresh_report();
  if (!quiet) {
    if (tty) std::cerr << '\n';
    std::cerr << "stopped: " << stop_reason_name(outcome.stopped_because) << " after iteration " << outcome.last_iteration << " ("
              << outcome.evaluations << " evaluations)\n";
  }
  const QdMetrics& m = outcome.metrics;
  std::cout << "run folder   " << store.dir().string() << "\n"
            << "archive      " << m.filled << " of " << m.cells << " cells (" << fixed(100.0 * m.coverage, 1)
            << " %), QD-score " << fixed(m.qd_score, 1) << ", best " << shown(m.best) << unit << ", mean elite "
            << shown(m.mean) << unit << "\n";
  if (checked) {
    const QdMetrics& c = checked->checked;
    std::cout << "checked      on " << me.check_replicas << " fresh replicas: QD-score " << fixed(c.qd_score, 1)
              << ", best " << shown(c.best) << unit << ", mean elite " << shown(c.mean) << unit << "; winner's curse "
              << fixed(checked->mean_winners_curse, 2) << unit << " per elite\n";
  }
  std::cout << "report       " << default_archive_report_path(store.dir()).string() << "\n"
            << "export with  sodaevo export " << store.dir().string() << " --archive --out DIR\n";
}

} // namespace sodaevo::app
