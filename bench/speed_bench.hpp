// The speed benchmark (`sodaevo bench speed`): frames per second and link updates
// per second of the engines on the bundled creatures, on synthetic creatures of 10
// to 100,000 links, and population throughput on 1 and all threads.
//
// Engines: "seed" (the seed paper's Algorithm 1-2, baselines.hpp), "plain" (the
// exact rules as a plain scalar loop, baselines.hpp), "reference" (soda::run, the
// plain SoA reference step), "fast-sse2" (FastStepper on the portable x86-64
// level) and "fast" (FastStepper on the best level of this CPU): each steps ONE
// creature alone. "fast-batch" (BatchStepper) steps kBenchBatch different
// creatures (copies with shifted muscle phases, so no sine is shared) on one core
// and counts creature-frames: the throughput per core of a population of one shape
// (lockstep where the CPU has AVX-512), not the speed of one creature.
// "fast-batch-fused" steps the same copies fused (lockstep off: the path of the
// GA's populations of mixed shapes); "fast-batch-same" steps kBenchBatch identical
// copies fused, which share every sine (the fused path's best case).
// "seed-batch" and "plain-batch" step fast-batch's creatures one after the other
// with the baselines; the batched engines' ratios are taken against them (the same
// creatures on both sides of a ratio).
// "fast-no-wave" (creature section) steps the creature alone with its wave
// amplitude at 0: not its motion, but its frame without the sines, which tells
// how much of one creature's time alone is the sines and how much the frame.
//
// Method: every figure is the median of `runs` timed runs; a run steps the engine
// from the model's initial state for a frame count calibrated so that one run takes
// about `target_seconds`. The engines' runs are interleaved (run 1 of every engine,
// then run 2, ...) so that a slow phase of the machine hits all of them, and a
// ratio is the median over the rounds of the ratio within each round (11 rounds,
// 3 with --quick). The GA section steps every creature of a saved run's
// generations, prepared as the GA evaluates them, with the seed baseline and the
// plain loop one after the other, a FastStepper each, and the GA's own batches
// (fast-batch): the exact mode's speed on the creatures it is used for. The
// population section runs 31 rounds of short runs, its
// 1-thread runs held to each core in turn (speed_bench.cpp says why).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace sodaevo::bench {

struct SpeedOptions {
  bool quick = false;        ///< shorter runs, fewer repeats, smaller sweep
  int threads = 0;           ///< "all threads" for the population (0 = all cores)
  bool creature_section = true;   ///< 1. the bundled creatures, every engine
  bool size_section = true;       ///< 2. the size sweep
  bool population_section = true; ///< 3. population throughput, 1 and all threads
  bool ga_section = true;         ///< 4. the GA's own creatures from a saved run
  /// The saved run whose creatures the GA section steps (every saved generation;
  /// the first and the last with `quick`); empty: no GA section.
  std::string ga_run;
  /// The SIMD level every engine takes for Auto (soda::force_simd_level): "auto" is
  /// the CPU's best; a lower one measures that level's kernels on this machine.
  std::string simd = "auto";
  /// Time the creature, size and GA sections by the thread's CPU time, not the
  /// wall clock (a machine shared with other work); the population section is wall time.
  bool cpu_time = false;
  std::vector<std::pair<std::string, std::string>> creatures; ///< name, model path
  std::function<void(const std::string&)> progress;          ///< one line per step
};

struct SpeedRow {
  std::string section;  ///< "creature", "size", "population" or "ga"
  std::string creature; ///< creature name (or "synthetic")
  std::string engine;
  int threads = 1;
  int batch = 1;        ///< creatures stepped together on one core (fast-batch); frames count creature-frames
  int masses = 0;
  int links = 0;        ///< springs and muscles (link updates per frame)
  long long frames = 0; ///< frames per timed run (population: per creature)
  int runs = 0;
  double median_seconds = 0.0;
  double frames_per_second = 0.0;
  double link_updates_per_second = 0.0;
  double speedup_vs_seed = 0.0;  ///< this engine / seed, same creature, same invocation
  double speedup_vs_plain = 0.0; ///< this engine / plain
  /// fast-replicas' replica-frames/s / fast-batch's creature-frames/s, the median
  /// over the rounds of the ratio within each round (ga section; 0: not measured)
  double speedup_vs_batch = 0.0;
};

/// A divider-bound control item's 2-thread speed-up below this: the two virtual
/// cores shared one physical core in that round (it is 2x on two cores, 1x on one).
inline constexpr double kSharedCoreBelow = 1.5;

/// A round's population speed-up above this many times the thread count cannot
/// come from one host state: its runs saw different ones.
inline constexpr double kAboveIdeal = 1.025;

/// The population's 1-thread runs are held to at most this many cores in turn
/// (each costs one run per round).
inline constexpr int kMaxHeldCores = 4;

/// One timed run of the population section (speed_rounds.csv has one row each).
struct PopulationRun {
  int round = 0;
  std::string work;   ///< "arithmetic" or "divider" (control items), "fast" or "fast-batch"
  int threads = 1;
  int core = -1;      ///< the core a 1-thread population run was pinned to; -1: not pinned
  double seconds = 0.0;
  double steal_ms = -1.0; ///< steal time accounted to the virtual CPUs during the run (all of them); -1: unknown
};

struct SpeedReport {
  std::vector<SpeedRow> rows;
  std::string simd;          ///< level of "fast"
  std::string lockstep;      ///< level of the lockstep lanes (fast-batch, fast-replicas), "none" without
  std::string cpu;           ///< the CPU's model name (/proc/cpuinfo), "" where unknown
  bool cpu_time = false;     ///< timed by the thread's CPU time (SpeedOptions::cpu_time)
  int population_threads = 1;
  /// All-thread rate / 1-thread rate, the median over the rounds of the ratio within
  /// each round; the 1-thread rate is the mean over the cores of a run pinned to each.
  double population_speedup = 0.0;
  double population_batch_speedup = 0.0; ///< the same for the batch path
  /// The same against the faster core's 1-thread run alone (what an unpinned run
  /// gets where the operating system keeps it on the faster core).
  double population_speedup_vs_faster_core = 0.0;
  /// Median over the rounds of the slowest core's 1-thread time / the fastest one's
  /// (one stepper per creature).
  double core_speed_spread = 1.0;
  int pinned_cores = 0; ///< cores every 1-thread run was held to in turn (0: not held)
  double one_thread_run_seconds = 0.0; ///< median time of one 1-thread run (one by one)
  /// population_speedup and population_batch_speedup over the rounds whose
  /// divider-bound items got at least kSharedCoreBelow (two physical cores); 0 if none.
  double population_speedup_two_cores = 0.0;
  double population_batch_speedup_two_cores = 0.0;
  int above_ideal_rounds = 0; ///< rounds whose one-by-one ratio exceeds kAboveIdeal x threads
  /// The same ratio for work items of arithmetic alone that share nothing, timed in
  /// the same rounds: what the machine gave a second busy thread at the time.
  double host_speedup = 0.0;
  /// The same for work items bound by the square-root/divide unit (like the step):
  /// about 1x where the host runs both virtual cores on one physical core.
  double host_divider_speedup = 0.0;
  int population_rounds = 0;
  std::vector<PopulationRun> population_runs; ///< every timed run, for speed_rounds.csv
  int shared_core_rounds = 0; ///< rounds whose divider-bound items got below kSharedCoreBelow
  double best_link_updates_per_second = 0.0; ///< fast, one thread, any size
  int best_links = 0;
  /// GA section: the run, its saved generations stepped, their creatures (prepared
  /// as the GA evaluates them), those the GA refuses, and their mean link count.
  std::string ga_run;
  int ga_generations = 0;
  int ga_creatures = 0;
  int ga_refused = 0;
  double ga_mean_links = 0.0;
};

SpeedReport run_speed_bench(const SpeedOptions& options);

/// Creatures fused on one core in the "fast-batch" rows.
inline constexpr int kBenchBatch = 16;

/// The physical limit the issue quotes: 0.5-1 billion link updates per second per
/// core; fractions are reported against the upper end.
inline constexpr double kPhysicalLimitLinkUpdatesPerSecond = 1e9;

} // namespace sodaevo::bench
