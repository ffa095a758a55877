// `sodaevo bench speed`: the speed benchmark (bench/speed_bench.hpp) with its CSV,
// SVG charts and a Markdown table under results/bench/.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.hpp"
#include "app/fixed_text.hpp"
#include "app/svg_chart.hpp"
#include "bench/speed_bench.hpp"
#include "core/batch_step.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"

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
};

std::string sci(double v) { return soda::format_printf("%.4g", v); }

std::string csv(const bench::SpeedReport& r) {
  std::ostringstream o;
  o << "section,creature,engine,threads,masses,links,frames_per_run,runs,median_seconds,frames_per_second,"
       "link_updates_per_second,speedup_vs_seed,speedup_vs_plain,batch\n";
  for (const bench::SpeedRow& row : r.rows) {
    o << row.section << ',' << row.creature << ',' << row.engine << ',' << row.threads << ',' << row.masses << ','
      << row.links << ',' << row.frames << ',' << row.runs << ',' << sci(row.median_seconds) << ','
      << sci(row.frames_per_second) << ',' << sci(row.link_updates_per_second) << ',' << fixed(row.speedup_vs_seed, 2)
      << ',' << fixed(row.speedup_vs_plain, 2) << ',' << row.batch << '\n';
  }
  return o.str();
}

/// Every timed run of the population section; the ratios in speed.md are medians
/// over the rounds of ratios formed from these.
std::string rounds_csv(const bench::SpeedReport& r) {
  std::ostringstream o;
  o << "round,work,threads,core,seconds,steal_ms\n";
  for (const bench::PopulationRun& run : r.population_runs) {
    o << run.round << ',' << run.work << ',' << run.threads << ',' << (run.core < 0 ? "-" : std::to_string(run.core))
      << ',' << soda::format_printf("%.6g", run.seconds) << ','
      << (run.steal_ms < 0.0 ? std::string("-") : soda::format_printf("%.6g", run.steal_ms)) << '\n';
  }
  return o.str();
}

/// What the kernel's steal time says of the population runs: time the hypervisor
/// gave the virtual CPUs' turn to something else (another guest), which a busy
/// sibling hardware thread does not show.
std::string steal_sentence(const std::vector<bench::PopulationRun>& runs) {
  double steal = 0.0, seconds = 0.0;
  int with_steal = 0;
  for (const bench::PopulationRun& run : runs) {
    if (run.steal_ms < 0.0) return "The kernel's steal time could not be read (/proc/stat).";
    steal += run.steal_ms;
    seconds += run.seconds;
    if (run.steal_ms > 0.0) ++with_steal;
  }
  return "Steal time the kernel accounted to the virtual CPUs during the timed runs (hypervisor preemption; in "
         "clock ticks): " +
         soda::format_printf("%.0f", steal) + " ms over " + soda::format_printf("%.1f", seconds) + " s of runs, in " +
         std::to_string(with_steal) + " of " + std::to_string(runs.size()) + " runs.";
}

std::string human(double v) { return format_tick(v); }

/// What bounds one creature alone, from the creature rows: its frame with and
/// without the sines (fast, fast-no-wave) against the time 20x the seed allows.
std::string one_creature_bound(const bench::SpeedReport& r) {
  std::map<std::string, std::map<std::string, const bench::SpeedRow*>> by_creature;
  std::vector<std::string> order;
  for (const bench::SpeedRow& row : r.rows) {
    if (row.section != "creature") continue;
    if (!by_creature.count(row.creature)) order.push_back(row.creature);
    by_creature[row.creature][row.engine] = &row;
  }
  std::ostringstream o;
  const auto ns = [](double frames_per_second) { return fixed(1e9 / frames_per_second, 1) + " ns"; };
  for (const std::string& name : order) {
    const auto& e = by_creature[name];
    if (!e.count("fast") || !e.count("fast-no-wave") || !e.count("seed")) continue;
    if (o.tellp() == 0) {
      o << "\nOne creature alone runs its frames one after the other: each frame's positions depend on the "
           "last through the links' lengths (a square root), their impulse factors (a division), each mass's "
           "additions in file order and the mass update. Its muscles' sines do not depend on them (they are "
           "computed ahead, in rows) and take their own time. A frame with and without the sines:\n\n";
    }
    const bench::SpeedRow& fast = *e.at("fast");
    const bench::SpeedRow& still = *e.at("fast-no-wave");
    const bench::SpeedRow& seed = *e.at("seed");
    o << "- " << name << ": " << ns(fast.frames_per_second) << " (fast, " << fixed(fast.speedup_vs_seed, 1)
      << "x the seed); " << ns(still.frames_per_second) << " without the sines (fast-no-wave, "
      << fixed(still.speedup_vs_seed, 1) << "x); 20x the seed would take " << ns(20.0 * seed.frames_per_second)
      << ".\n";
  }
  return o.str();
}

std::string markdown(const bench::SpeedReport& r, const std::string& command) {
  std::ostringstream o;
  o << "Measured with `" << command << "` (fast = " << r.simd
    << "; rates: medians of the runs; ratios: the median over the rounds of runs of the ratio within each "
       "round, all within this one invocation).\n\n";
  o << "\"fast\" steps one creature alone. \"fast-batch\" steps " << bench::kBenchBatch
    << " different creatures (copies with their muscle phases shifted, no sine shared) on one core as "
       "soda::BatchStepper does and counts creature-frames: it is the throughput per core of a population "
       "of one shape, not the speed of a single creature. The copies have one shape, so they run in "
       "lockstep, one creature per AVX-512 lane (soda::LockstepBatch), where the CPU has it; the genetic "
       "algorithm's populations, of mixed shapes, take the fused path. "
       "\"fast-batch-fused\" steps the same "
    << bench::kBenchBatch << " in fused scenes (lockstep off; at most " << soda::kMaxFusedLinks
    << " links per scene, whose links share SIMD batches): the path of a population of mixed shapes. "
       "\"fast-batch-same\" steps "
    << bench::kBenchBatch
    << " identical copies fused, which share every muscle sine (the fused path's best case). "
       "All are bit-exact against the reference step. \"seed-batch\" and \"plain-batch\" step the same "
    << bench::kBenchBatch
    << " different creatures as fast-batch one after the other with the seed baseline and the plain loop (a "
       "population as those programs evaluate it); the ratios of the batched engines (fast-batch, "
       "fast-batch-fused, fast-batch-same) are taken against these, so that both sides of each ratio step the "
       "same creatures. \"fast-no-wave\" steps the creature alone with its wave "
       "amplitude set to 0: no sines, the muscles held at their rest lengths. It is not the creature's motion "
       "but the cost of its frame without the sines (below).\n\n";
  auto has = [&](const char* section) {
    const auto in_section = [&](const bench::SpeedRow& row) { return row.section == section; };
    return std::any_of(r.rows.begin(), r.rows.end(), in_section);
  };
  if (has("creature")) {
    o << "| creature | links | engine | frames/s | link updates/s | vs seed | vs plain |\n";
    o << "|---|---:|---|---:|---:|---:|---:|\n";
  }
  for (const bench::SpeedRow& row : r.rows) {
    if (row.section != "creature") continue;
    o << "| " << row.creature << " | " << row.links << " | " << row.engine << " | " << human(row.frames_per_second)
      << " | " << human(row.link_updates_per_second) << " | " << fixed(row.speedup_vs_seed, 1) << "x | "
      << fixed(row.speedup_vs_plain, 2) << "x |\n";
  }
  o << one_creature_bound(r);
  std::map<int, std::map<std::string, double>> sweep;
  std::vector<std::string> engines;
  for (const bench::SpeedRow& row : r.rows) {
    if (row.section != "size") continue;
    sweep[row.links][row.engine] = row.link_updates_per_second;
    if (std::find(engines.begin(), engines.end(), row.engine) == engines.end()) engines.push_back(row.engine);
  }
  if (!sweep.empty()) {
    o << "\nSize sweep (synthetic lattices), link updates per second, one thread:\n\n| links |";
    for (const auto& e : engines) o << ' ' << e << " |";
    o << " fast vs seed | fast vs plain |\n|---:|";
    for (std::size_t i = 0; i < engines.size() + 2; ++i) o << "---:|";
    o << '\n';
  }
  for (const auto& [links, by_engine] : sweep) {
    o << "| " << links << " |";
    for (const auto& e : engines) o << ' ' << human(by_engine.count(e) ? by_engine.at(e) : 0.0) << " |";
    const double fast = by_engine.count("fast") ? by_engine.at("fast") : 0.0;
    const double seed = by_engine.count("seed") ? by_engine.at("seed") : 0.0;
    const double plain = by_engine.count("plain") ? by_engine.at("plain") : 0.0;
    o << ' ' << (seed > 0 ? fixed(fast / seed, 1) : "-") << "x | " << (plain > 0 ? fixed(fast / plain, 2) : "-")
      << "x |\n";
  }
  if (has("ga")) {
    o << "\nThe GA's own creatures, one core: the " << r.ga_creatures << " creatures of " << r.ga_generations
      << " saved generations of `" << r.ga_run << "` (" << fixed(r.ga_mean_links, 1)
      << " links on average), prepared as the GA evaluates them";
    if (r.ga_refused > 0) o << " (" << r.ga_refused << " the GA refuses are left out)";
    o << ". seed and plain step them one after the other, fast with a FastStepper each, fast-batch in the batches "
         "the GA's evaluation cuts on one thread (soda::BatchStepper, fused scenes and lockstep as the shapes "
         "allow); frames/s count creature-frames:\n\n";
    o << "| engine | creature-frames/s | link updates/s | vs seed | vs plain |\n|---|---:|---:|---:|---:|\n";
    for (const bench::SpeedRow& row : r.rows) {
      if (row.section != "ga") continue;
      o << "| " << row.engine << " | " << human(row.frames_per_second) << " | " << human(row.link_updates_per_second)
        << " | " << fixed(row.speedup_vs_seed, 1) << "x | " << fixed(row.speedup_vs_plain, 2) << "x |\n";
    }
  }
  if (has("population")) {
    o << "\nPopulation throughput (every creature stepped from scratch, results by index; fast = a "
         "FastStepper per creature, fast-batch = batches of at most "
      << bench::kBenchBatch << " creatures on one core as soda::BatchStepper steps them, cut where a new fused "
         "scene starts (here each batch is 16 copies of one creature: lockstep where the CPU has AVX-512); "
         "no two creatures share a sine):\n\n";
    o << "| engine | threads | creatures x frames | creature-frames/s | link updates/s |\n|---|---:|---|---:|---:|\n";
    for (const bench::SpeedRow& row : r.rows) {
      if (row.section != "population") continue;
      o << "| " << row.engine << " | " << row.threads << " | " << row.creature << " x " << row.frames << " | "
        << human(row.frames_per_second) << " | " << human(row.link_updates_per_second) << " |\n";
    }
    if (r.population_threads == 1) {
      o << "\nOne thread only (--threads 1): no speed-up to report.\n";
    } else {
      const std::string n = std::to_string(r.population_threads);
      o << "\n" << n << "-thread / 1-thread population throughput: " << fixed(r.population_speedup, 2) << "x (fast), "
        << fixed(r.population_batch_speedup, 2) << "x (fast-batch): the median over " << r.population_rounds
        << " rounds of the ratio of rates within each round, where ";
      if (r.pinned_cores > 0) {
        o << "the 1-thread rate is the mean of the rates of a run held to each of " << r.pinned_cores
          << " cores in turn";
      } else {
        o << "the 1-thread run was not held to a core";
      }
      o << " and the " << n << "-thread run is not held (the table's rates are medians of each run's rate, so "
        << "their ratio differs a little). A 1-thread run took about " << fixed(1000.0 * r.one_thread_run_seconds, 0)
        << " ms. Control items that share nothing, timed in the same rounds: " << fixed(r.host_speedup, 2)
        << "x for chains of arithmetic bound by their own latency, " << fixed(r.host_divider_speedup, 2)
        << "x for items bound by the square-root/divide unit as the step is. The latter fell below "
        << fixed(bench::kSharedCoreBelow, 1) << "x in " << r.shared_core_rounds << " of " << r.population_rounds
        << " rounds (on this project's machine: the host ran both virtual cores on one physical core, whose unit "
           "they then share)";
      if (r.shared_core_rounds < r.population_rounds) {
        o << "; over the other " << r.population_rounds - r.shared_core_rounds << " rounds the population's medians are "
          << fixed(r.population_speedup_two_cores, 2) << "x (fast) and " << fixed(r.population_batch_speedup_two_cores, 2)
          << "x (fast-batch)";
      }
      o << ". ";
      if (r.pinned_cores > 0) {
        o << "The slowest core's 1-thread time over the fastest's: " << fixed(r.core_speed_spread, 2)
          << "x (median over the rounds, fast); against the fastest core's run alone the fast ratio is "
          << fixed(r.population_speedup_vs_faster_core, 2) << "x. ";
      }
      o << "Rounds whose fast ratio exceeds " << fixed(bench::kAboveIdeal * r.population_threads, 2)
        << "x, which one host state cannot give (their runs saw different ones): " << r.above_ideal_rounds
        << ". " << steal_sentence(r.population_runs)
        << " speed_rounds.csv lists every timed run (round, work, threads, core, seconds, steal_ms).\n";
    }
  }
  if (!sweep.empty()) {
    o << "\nBest single-thread rate: " << human(r.best_link_updates_per_second) << " link updates/s (" << r.best_links
      << " links), " << fixed(100.0 * r.best_link_updates_per_second / bench::kPhysicalLimitLinkUpdatesPerSecond, 0)
      << " % of 1e9/s, the upper end of the 0.5-1e9/s physical limit per core.\n";
  }
  return o.str();
}

std::string sweep_svg(const bench::SpeedReport& r) {
  LineChart c;
  c.title = "Link updates per second vs creature size (one thread)";
  c.x_axis = {"links (springs + muscles)", true};
  c.y_axis = {"link updates per second", true};
  std::map<std::string, LineSeries> by_engine;
  std::vector<std::string> order;
  for (const bench::SpeedRow& row : r.rows) {
    if (row.section != "size") continue;
    if (!by_engine.count(row.engine)) order.push_back(row.engine);
    LineSeries& s = by_engine[row.engine];
    s.name = row.engine;
    s.x.push_back(row.links);
    s.y.push_back(row.link_updates_per_second);
  }
  for (const auto& e : order) c.series.push_back(by_engine[e]);
  LineSeries limit{"physical limit 1e9/s", {}, {}, false, true};
  if (!c.series.empty()) {
    limit.x = {c.series[0].x.front(), c.series[0].x.back()};
    limit.y = {bench::kPhysicalLimitLinkUpdatesPerSecond, bench::kPhysicalLimitLinkUpdatesPerSecond};
    c.series.push_back(limit);
  }
  return render_line_chart(c);
}

std::string creatures_svg(const bench::SpeedReport& r) {
  BarChart c;
  c.title = "Frames per second on the bundled creatures (one thread)";
  c.y_axis = {"frames per second", true};
  std::map<std::string, std::map<std::string, double>> fps;
  std::vector<std::string> engines;
  for (const bench::SpeedRow& row : r.rows) {
    if (row.section != "creature") continue;
    if (std::find(c.categories.begin(), c.categories.end(), row.creature) == c.categories.end()) {
      c.categories.push_back(row.creature);
    }
    if (std::find(engines.begin(), engines.end(), row.engine) == engines.end()) engines.push_back(row.engine);
    fps[row.engine][row.creature] = row.frames_per_second;
  }
  for (const auto& e : engines) {
    BarSeries s{e, {}};
    for (const auto& cat : c.categories) s.values.push_back(fps[e].count(cat) ? fps[e][cat] : 0.0);
    c.series.push_back(s);
  }
  return render_bar_chart(c);
}

void run_bench_speed(const BenchSpeedOptions& opt, const std::string& command) {
  bench::SpeedOptions so;
  so.quick = opt.quick;
  so.threads = opt.threads;
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
  const std::string table = markdown(report, command);
  std::cout << table;
  // A run of some sections does not overwrite the full results unless asked to.
  if (!all_sections && !opt.out_given) {
    std::cerr << "bench speed: some sections only: nothing written (pass --out DIR to write the files)\n";
    return;
  }
  fs::create_directories(opt.out);
  const fs::path out(opt.out);
  std::string written = (out / "speed.csv").string() + ", speed.md";
  soda::write_file_atomically(out / "speed.csv", csv(report));
  if (so.size_section) {
    soda::write_file_atomically(out / "speed.svg", sweep_svg(report));
    written += ", speed.svg";
  }
  if (so.creature_section) {
    soda::write_file_atomically(out / "speed_creatures.svg", creatures_svg(report));
    written += ", speed_creatures.svg";
  }
  if (so.population_section) {
    soda::write_file_atomically(out / "speed_rounds.csv", rounds_csv(report));
    written += ", speed_rounds.csv";
  }
  soda::write_file_atomically(out / "speed.md", table);
  std::cerr << "bench speed: wrote " << written << "\n";
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
  add_bench_accuracy_commands(*bench);
  speed->callback([opt, out, ga_run] {
    std::string command = "sodaevo bench speed";
    if (opt->quick) command += " --quick";
    if (opt->threads > 0) command += " --threads " + std::to_string(opt->threads);
    if (!opt->sections.empty()) {
      command += " --sections ";
      for (std::size_t i = 0; i < opt->sections.size(); ++i) command += (i ? "," : "") + opt->sections[i];
    }
    opt->out_given = out->count() > 0;
    opt->ga_run_given = ga_run->count() > 0;
    run_bench_speed(*opt, command);
  });
  add_bench_evolve_command(*bench);
}

} // namespace sodaevo::app
