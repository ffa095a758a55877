#include "bench/speed_report.hpp"

#include <algorithm>
#include <map>
#include <sstream>

#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "core/batch_step.hpp"
#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::bench {

using charts::fixed;

namespace {

bool has_section(const SpeedReport& r, const char* section) {
  const auto in_section = [&](const SpeedRow& row) { return row.section == section; };
  return std::any_of(r.rows.begin(), r.rows.end(), in_section);
}

std::string sci(double v) { return soda::format_printf("%.4g", v); }

/// What the kernel's steal time says of the population runs: time the hypervisor
/// gave the virtual CPUs' turn to something else (another guest), which a busy
/// sibling hardware thread does not show.
std::string steal_sentence(const std::vector<PopulationRun>& runs) {
  double steal = 0.0, seconds = 0.0;
  int with_steal = 0;
  for (const PopulationRun& run : runs) {
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

std::string human(double v) { return charts::format_tick(v); }

/// What bounds one creature alone, from the creature rows: its frame with and
/// without the sines (fast, fast-no-wave) against the time 20x the seed allows.
std::string one_creature_bound(const SpeedReport& r) {
  std::map<std::string, std::map<std::string, const SpeedRow*>> by_creature;
  std::vector<std::string> order;
  for (const SpeedRow& row : r.rows) {
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
    const SpeedRow& fast = *e.at("fast");
    const SpeedRow& still = *e.at("fast-no-wave");
    const SpeedRow& seed = *e.at("seed");
    o << "- " << name << ": " << ns(fast.frames_per_second) << " (fast, " << fixed(fast.speedup_vs_seed, 1)
      << "x the seed); " << ns(still.frames_per_second) << " without the sines (fast-no-wave, "
      << fixed(still.speedup_vs_seed, 1) << "x); 20x the seed would take " << ns(20.0 * seed.frames_per_second)
      << ".\n";
  }
  return o.str();
}

/// How the figures were measured and what each engine steps.
void intro_part(std::ostringstream& o, const SpeedReport& r, const std::string& command) {
  o << "Measured with `" << command << "`" << (r.cpu.empty() ? std::string() : " on " + r.cpu) << " (fast = " << r.simd
    << ", lockstep lanes = " << r.lockstep << (r.cpu_time ? "; timed by the thread's CPU time" : "") << "; rates: medians of the runs; ratios: the median over the rounds of runs of the ratio within each "
       "round, all within this one invocation).\n\n";
  o << "\"fast\" steps one creature alone. \"fast-batch\" steps " << kBenchBatch
    << " different creatures (copies with their muscle phases shifted, no sine shared) on one core as "
       "soda::BatchStepper does and counts creature-frames: it is the throughput per core of a population "
       "of one shape, not the speed of a single creature. The copies have one shape, so they run in "
       "lockstep, one creature per lane (soda::LockstepBatch: 8 lanes, one AVX-512 vector or two AVX2 ones), where the CPU has either; the genetic "
       "algorithm's populations, of mixed shapes, take the fused path. "
       "\"fast-batch-fused\" steps the same "
    << kBenchBatch << " in fused scenes (lockstep off; at most " << soda::kMaxFusedLinks
    << " links per scene, whose links share SIMD batches): the path of a population of mixed shapes. "
       "\"fast-batch-same\" steps "
    << kBenchBatch
    << " identical copies fused, which share every muscle sine (the fused path's best case). "
       "All are bit-exact against the reference step. \"seed-batch\" and \"plain-batch\" step the same "
    << kBenchBatch
    << " different creatures as fast-batch one after the other with the seed baseline and the plain loop (a "
       "population as those programs evaluate it); the ratios of the batched engines (fast-batch, "
       "fast-batch-fused, fast-batch-same) are taken against these, so that both sides of each ratio step the "
       "same creatures. \"fast-no-wave\" steps the creature alone with its wave "
       "amplitude set to 0: no sines, the muscles held at their rest lengths. It is not the creature's motion "
       "but the cost of its frame without the sines (below).\n\n";
}

/// 1. The bundled creatures: a row per engine, then what bounds one creature alone.
void creature_part(std::ostringstream& o, const SpeedReport& r) {
  if (has_section(r, "creature")) {
    o << "| creature | links | engine | frames/s | link updates/s | vs seed | vs plain |\n";
    o << "|---|---:|---|---:|---:|---:|---:|\n";
  }
  for (const SpeedRow& row : r.rows) {
    if (row.section != "creature") continue;
    o << "| " << row.creature << " | " << row.links << " | " << row.engine << " | " << human(row.frames_per_second)
      << " | " << human(row.link_updates_per_second) << " | " << fixed(row.speedup_vs_seed, 1) << "x | "
      << fixed(row.speedup_vs_plain, 2) << "x |\n";
  }
  o << one_creature_bound(r);
}

/// 2. The size sweep: link updates per second by size, a column per engine.
void size_part(std::ostringstream& o, const SpeedReport& r) {
  std::map<int, std::map<std::string, double>> sweep;
  std::vector<std::string> engines;
  for (const SpeedRow& row : r.rows) {
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
}

/// 4. The GA's own creatures from a saved run.
void ga_part(std::ostringstream& o, const SpeedReport& r) {
  o << "\nThe GA's own creatures, one core: the " << r.ga_creatures << " creatures of " << r.ga_generations
    << " saved generations of `" << r.ga_run << "` (" << fixed(r.ga_mean_links, 1)
    << " links on average), prepared as the GA evaluates them";
  if (r.ga_refused > 0) o << " (" << r.ga_refused << " the GA refuses are left out)";
  o << ". seed and plain step them one after the other, fast with a FastStepper each, fast-batch in the batches "
       "the GA's evaluation cuts on one thread (soda::BatchStepper, fused scenes and lockstep as the shapes "
       "allow), fast-replicas each creature as the GA's estimator scores it: 8 replicas of one Model (replica 0 "
       "exact, the others with sine jitter p = 0.002), in the same batches as fast-batch (16 creatures x 8 "
       "replicas, one BatchStepper each: every creature's replicas in one group of 8 lockstep lanes, the "
       "groups stepped frame by frame together). frames/s count creature-frames, replica-frames for "
       "fast-replicas; vs fast-batch is issue 26's target (at least 1.5x), the median over the rounds of the "
       "ratio within each round:\n\n";
  o << "| engine | creature-frames/s | link updates/s | vs seed | vs plain | vs fast-batch |\n"
       "|---|---:|---:|---:|---:|---:|\n";
  for (const SpeedRow& row : r.rows) {
    if (row.section != "ga") continue;
    o << "| " << row.engine << " | " << human(row.frames_per_second) << " | " << human(row.link_updates_per_second)
      << " | " << fixed(row.speedup_vs_seed, 1) << "x | " << fixed(row.speedup_vs_plain, 2) << "x | "
      << (row.speedup_vs_batch > 0.0 ? fixed(row.speedup_vs_batch, 2) + "x" : std::string("-")) << " |\n";
  }
}

/// 3. Population throughput on 1 and all threads, and what the host gave meanwhile.
void population_part(std::ostringstream& o, const SpeedReport& r) {
  o << "\nPopulation throughput (every creature stepped from scratch, results by index; fast = a "
       "FastStepper per creature, fast-batch = batches of at most "
    << kBenchBatch << " creatures on one core as soda::BatchStepper steps them, cut where a new fused "
       "scene starts (here each batch is 16 copies of one creature: lockstep where the CPU has AVX2 or AVX-512); "
       "no two creatures share a sine):\n\n";
  o << "| engine | threads | creatures x frames | creature-frames/s | link updates/s |\n|---|---:|---|---:|---:|\n";
  for (const SpeedRow& row : r.rows) {
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
      << fixed(kSharedCoreBelow, 1) << "x in " << r.shared_core_rounds << " of " << r.population_rounds
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
    o << "Rounds whose fast ratio exceeds " << fixed(kAboveIdeal * r.population_threads, 2)
      << "x, which one host state cannot give (their runs saw different ones): " << r.above_ideal_rounds
      << ". " << steal_sentence(r.population_runs)
      << " speed_rounds.csv lists every timed run (round, work, threads, core, seconds, steal_ms).\n";
  }
}

/// The best single-thread rate of the size sweep against the physical limit.
void best_rate_part(std::ostringstream& o, const SpeedReport& r) {
  o << "\nBest single-thread rate: " << human(r.best_link_updates_per_second) << " link updates/s (" << r.best_links
    << " links), " << fixed(100.0 * r.best_link_updates_per_second / kPhysicalLimitLinkUpdatesPerSecond, 0)
    << " % of 1e9/s, the upper end of the 0.5-1e9/s physical limit per core.\n";
}

} // namespace

std::string speed_csv(const SpeedReport& r) {
  std::ostringstream o;
  o << "section,creature,engine,threads,masses,links,frames_per_run,runs,median_seconds,frames_per_second,"
       "link_updates_per_second,speedup_vs_seed,speedup_vs_plain,batch,speedup_vs_batch\n";
  for (const SpeedRow& row : r.rows) {
    o << row.section << ',' << row.creature << ',' << row.engine << ',' << row.threads << ',' << row.masses << ','
      << row.links << ',' << row.frames << ',' << row.runs << ',' << sci(row.median_seconds) << ','
      << sci(row.frames_per_second) << ',' << sci(row.link_updates_per_second) << ',' << fixed(row.speedup_vs_seed, 2)
      << ',' << fixed(row.speedup_vs_plain, 2) << ',' << row.batch << ',' << fixed(row.speedup_vs_batch, 2) << '\n';
  }
  return o.str();
}

/// Every timed run of the population section; the ratios in speed.md are medians
/// over the rounds of ratios formed from these.
std::string speed_rounds_csv(const SpeedReport& r) {
  std::ostringstream o;
  o << "round,work,threads,core,seconds,steal_ms\n";
  for (const PopulationRun& run : r.population_runs) {
    o << run.round << ',' << run.work << ',' << run.threads << ',' << (run.core < 0 ? "-" : std::to_string(run.core))
      << ',' << soda::format_printf("%.6g", run.seconds) << ','
      << (run.steal_ms < 0.0 ? std::string("-") : soda::format_printf("%.6g", run.steal_ms)) << '\n';
  }
  return o.str();
}

std::string speed_markdown(const SpeedReport& r, const std::string& command) {
  std::ostringstream o;
  intro_part(o, r, command);
  creature_part(o, r);
  size_part(o, r);
  if (has_section(r, "ga")) ga_part(o, r);
  if (has_section(r, "population")) population_part(o, r);
  if (has_section(r, "size")) best_rate_part(o, r);
  return o.str();
}

std::string speed_sweep_svg(const SpeedReport& r) {
  charts::LineChart c;
  c.title = "Link updates per second vs creature size (one thread)";
  c.x_axis = {"links (springs + muscles)", true};
  c.y_axis = {"link updates per second", true};
  std::map<std::string, charts::LineSeries> by_engine;
  std::vector<std::string> order;
  for (const SpeedRow& row : r.rows) {
    if (row.section != "size") continue;
    if (!by_engine.count(row.engine)) order.push_back(row.engine);
    charts::LineSeries& s = by_engine[row.engine];
    s.name = row.engine;
    s.x.push_back(row.links);
    s.y.push_back(row.link_updates_per_second);
  }
  for (const auto& e : order) c.series.push_back(by_engine[e]);
  charts::LineSeries limit{"physical limit 1e9/s", {}, {}, false, true};
  if (!c.series.empty()) {
    limit.x = {c.series[0].x.front(), c.series[0].x.back()};
    limit.y = {kPhysicalLimitLinkUpdatesPerSecond, kPhysicalLimitLinkUpdatesPerSecond};
    c.series.push_back(limit);
  }
  return charts::render_line_chart(c);
}

std::string speed_creatures_svg(const SpeedReport& r) {
  charts::BarChart c;
  c.title = "Frames per second on the bundled creatures (one thread)";
  c.y_axis = {"frames per second", true};
  std::map<std::string, std::map<std::string, double>> fps;
  std::vector<std::string> engines;
  for (const SpeedRow& row : r.rows) {
    if (row.section != "creature") continue;
    if (std::find(c.categories.begin(), c.categories.end(), row.creature) == c.categories.end()) {
      c.categories.push_back(row.creature);
    }
    if (std::find(engines.begin(), engines.end(), row.engine) == engines.end()) engines.push_back(row.engine);
    fps[row.engine][row.creature] = row.frames_per_second;
  }
  for (const auto& e : engines) {
    charts::BarSeries s{e, {}};
    for (const auto& cat : c.categories) s.values.push_back(fps[e].count(cat) ? fps[e][cat] : 0.0);
    c.series.push_back(s);
  }
  return charts::render_bar_chart(c);
}

std::vector<std::string> write_speed_files(const std::filesystem::path& out, const SpeedReport& report,
                                           const SpeedOptions& options, const std::string& markdown) {
  std::filesystem::create_directories(out);
  std::vector<std::string> written = {"speed.csv", "speed.md"};
  soda::write_file_atomically(out / "speed.csv", speed_csv(report));
  if (options.size_section) {
    soda::write_file_atomically(out / "speed.svg", speed_sweep_svg(report));
    written.push_back("speed.svg");
  }
  if (options.creature_section) {
    soda::write_file_atomically(out / "speed_creatures.svg", speed_creatures_svg(report));
    written.push_back("speed_creatures.svg");
  }
  if (options.population_section) {
    soda::write_file_atomically(out / "speed_rounds.csv", speed_rounds_csv(report));
    written.push_back("speed_rounds.csv");
  }
  soda::write_file_atomically(out / "speed.md", markdown); // last: it sums up the files beside it
  return written;
}

} // namespace sodaevo::bench
