#include "bench/evolve_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::bench {

using charts::fixed;

namespace {

const char* method_label(const std::string& m) {
  if (m == "ga") return "genetic algorithm";
  if (m == "random") return "random search";
  return "hill climber (1+1)";
}

std::string comparison_csv(const SearchComparison& c) {
  std::ostringstream o;
  o << "method,seed,evaluations,best_fitness_at_common_budget,best_px_per_frame\n";
  for (const SearchRun& r : c.runs) {
    o << r.method << ',' << r.seed << ',' << c.evaluations << ',' << fixed(best_after(r, c.evaluations), 6)
      << ',' << fixed(r.best_px_per_frame, 6) << '\n';
  }
  return o.str();
}

std::string comparison_svg(const SearchComparison& c, long long frames) {
  charts::LineChart chart;
  chart.title = "Best distance walked vs evaluations (median over seeds)";
  chart.x_axis = {"evaluations", false};
  chart.y_axis = {"best fitness: px per frame", false};
  for (const char* m : {"ga", "random", "hill"}) {
    charts::LineSeries s;
    s.name = method_label(m);
    s.markers = false;
    const long long step = std::max<long long>(1, c.evaluations / 60);
    for (long long e = step; e <= c.evaluations; e += step) {
      s.x.push_back(static_cast<double>(e));
      s.y.push_back(median_best(c, m, e) / static_cast<double>(frames));
    }
    chart.series.push_back(std::move(s));
  }
  return charts::render_line_chart(chart);
}

} // namespace

FullRun run_full_evolution(const RunConfig& config, const std::filesystem::path& out, int threads,
                           const std::string& command, const std::function<void(const std::string&)>& say) {
  FullRun full;
  full.run_dir = (out / ("evolve-run-" + config.name)).string();
  RunStore store = RunStore::create(full.run_dir, config, true, command);
  ThreadEvaluator evaluator(threads);
  EvolutionOptions eo;
  eo.on_generation = [&](const Progress& p) {
    if (p.generation % 10 == 0 || p.generation + 1 == p.generations) {
      say("full run: generation " + std::to_string(p.generation) + "/" + std::to_string(p.generations) + ", best " +
          fixed(p.stats.best / static_cast<double>(config.fitness.frames), 3) + " px/frame");
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
    soda::write_model_file(out / "evolve_champion.xml",
                           roles_of(config).problem->export_form(champion.creature, champion.id, champion.evaluation));
  }
  return full;
}

std::string evolve_markdown(const EvolveReport& r) {
  const SearchComparison& c = r.comparison;
  const double frames = static_cast<double>(r.config.fitness.frames);
  std::ostringstream md;
  md << "Measured with `" << r.command << "` (" << r.seeds << " seeds; fitness: " << r.config.fitness.frames
     << " frames after " << r.config.fitness.settle_frames << " settle frames, "
     << (r.config.fitness.scaling == FitnessScaling::Sodarace ? "Sodarace scaling" : "no scaling") << ").\n\n";
  md << "Search methods at equal evaluations (" << c.evaluations << " each = " << r.generations
     << " GA generations of " << r.config.population.size << "), best fitness in px/frame:\n\n";
  md << "| method | median best | min | max |\n|---|---:|---:|---:|\n";
  for (const char* m : {"ga", "random", "hill"}) {
    double lo = INFINITY, hi = -INFINITY;
    for (const SearchRun& run : c.runs) {
      if (run.method != m) continue;
      const double b = best_after(run, c.evaluations);
      lo = std::min(lo, b);
      hi = std::max(hi, b);
    }
    md << "| " << method_label(m) << " | " << fixed(median_best(c, m, c.evaluations) / frames, 3)
       << " | " << fixed(lo / frames, 3) << " | " << fixed(hi / frames, 3) << " |\n";
  }
  const double ga = median_best(c, "ga", c.evaluations);
  const double rs = median_best(c, "random", c.evaluations);
  const double hc = median_best(c, "hill", c.evaluations);
  md << "\nGA / random search: " << fixed(ga / rs, 2) << "x; GA / hill climber: " << fixed(ga / hc, 2)
     << "x (medians). Comparison wall time " << fixed(r.comparison_seconds, 1) << " s.\n\n";
  md << "Dainty Walker under the same fitness settings: " << fixed(r.classic.forward_px_per_frame, 3)
     << " px/frame with its wave as written, " << fixed(r.classic.reversed_px_per_frame, 3)
     << " reversed; best in the configured direction " << fixed(r.classic.best_fitness_px_per_frame, 3) << " px/frame.\n";
  if (r.full.done) {
    const double champion = r.full.best_fitness / frames;
    md << "\nFull run of `" << r.config_path << "` (" << r.full.generations << " generations, " << r.full.evaluations
       << " evaluations, " << (r.threads > 0 ? std::to_string(r.threads) : std::string("all")) << " threads): "
       << fixed(r.full.wall_seconds, 1) << " s, champion " << r.full.best_id << " at " << fixed(champion, 3)
       << " px/frame = " << fixed(champion / r.classic.best_fitness_px_per_frame, 2)
       << "x the Dainty Walker's best. Champion: `evolve_champion.xml`; run folder (not committed): `" << r.full.run_dir << "`.\n";
  }
  return md.str();
}

std::string write_evolve_files(const std::filesystem::path& out, const EvolveReport& report) {
  const std::string markdown = evolve_markdown(report);
  std::filesystem::create_directories(out);
  soda::write_file_atomically(out / "evolve.csv", comparison_csv(report.comparison));
  soda::write_file_atomically(out / "evolve.svg", comparison_svg(report.comparison, report.config.fitness.frames));
  soda::write_file_atomically(out / "evolve.md", markdown);
  return markdown;
}

} // namespace sodaevo::bench
