// 3. Population throughput (`sodaevo bench speed`): every creature evaluated from
// scratch by index, on 1 thread and on all threads, one by one and in the batches
// the GA cuts, in many short rounds beside control items that share nothing
// (host_probes.hpp), so that the thread speed-up can be told from what the host
// gave a second thread at the time.
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/host_probes.hpp"
#include "bench/median.hpp"
#include "bench/speed_engines.hpp"
#include "bench/speed_sections.hpp"
#include "core/batch_step.hpp"
#include "core/fast_step.hpp"
#include "core/number_text.hpp"
#include "core/simd_level.hpp"
#include "evolve/evaluators/parallel_for.hpp"

namespace sodaevo::bench {

namespace {

std::string fmt(const char* f, double v) { return soda::format_printf(f, v); }

/// The time a run would take at the mean of the rates of `per_core` runs.
double at_mean_rate(const std::vector<double>& per_core) {
  double rate = 0.0;
  for (double t : per_core) rate += 1.0 / t;
  return static_cast<double>(per_core.size()) / rate;
}

} // namespace

void time_population_section(const SpeedSectionInput& in, SpeedReport& report) {
  if (in.creatures.empty()) return;
  const int all = resolve_thread_count(in.options.threads);
  report.population_threads = all;
  // Short runs (about 50 ms on one thread) in many rounds: this host changes how
  // fast each virtual core runs (what its physical core's other thread does) within
  // a fraction of a second, and a ratio means something only where its two runs saw
  // the same state. Longer runs in fewer rounds straddled such changes, and their
  // median ratio swung from one invocation to the next (bench/README.md, "Tenth
  // session").
  // 16 copies of each bundled creature per two threads (48 creatures on this
  // machine): about 50 ms on one thread, and enough batch items to keep every
  // thread busy.
  const int copies = (in.options.quick ? 4 : 16) * std::max(1, all / 2);
  const long long frames = in.options.quick ? 1000 : 5000;
  const std::size_t count = in.creatures.size() * static_cast<std::size_t>(copies);
  // Creature i is copy i / 3 of bundled creature i % 3, its muscle phases shifted
  // (shifted_copy) so that no two creatures share a sine.
  std::vector<soda::Model> population;
  for (std::size_t i = 0; i < count; ++i) {
    population.push_back(shifted_copy(in.creatures[i % in.creatures.size()].second, static_cast<int>(i / in.creatures.size())));
  }
  long long links_per_round = 0;
  std::vector<int> population_links;
  for (const soda::Model& m : population) {
    links_per_round += m.link_count();
    population_links.push_back(m.link_count());
  }
  std::vector<double> results(count), batch_results(count);
  auto evaluate = [&](int threads) {
    const auto t0 = Clock::now();
    parallel_for_index(count, threads, [&](std::size_t i) {
      const soda::Model& model = population[i];
      soda::FastStepper stepper(model, frames);
      soda::State s = soda::make_state(model);
      stepper.run(s, frames);
      results[i] = soda::mass_centroid(model, s).x;
    });
    return seconds_since(t0);
  };
  // The batch path (the GA's, ThreadEvaluator in evolve/evaluators/evaluator.cpp): each work item is a
  // batch of at most kBenchBatch consecutive creatures fused on one core, cut
  // where a new fused scene starts (soda::fused_batch_ends), results by index.
  const std::vector<std::size_t> batch_ends = soda::fused_batch_ends(population_links, kBenchBatch);
  auto evaluate_batches = [&](int threads) {
    const auto t0 = Clock::now();
    parallel_for_index(batch_ends.size(), threads, [&](std::size_t b) {
      const std::size_t first = b == 0 ? 0 : batch_ends[b - 1], last = batch_ends[b];
      std::vector<const soda::Model*> models;
      std::vector<soda::State> states;
      for (std::size_t i = first; i < last; ++i) {
        models.push_back(&population[i]);
        states.push_back(soda::make_state(*models.back()));
      }
      std::vector<soda::State*> ptrs;
      for (soda::State& s : states) ptrs.push_back(&s);
      soda::BatchStepper stepper(models, frames);
      stepper.run(ptrs, frames);
      for (std::size_t i = first; i < last; ++i) batch_results[i] = soda::mass_centroid(*models[i - first], states[i - first]).x;
    });
    return seconds_since(t0);
  };
  in.say("population of " + std::to_string(count) + " creatures x " + std::to_string(frames) + " frames, 1 and " +
      std::to_string(all) + " threads, one by one and in " + std::to_string(batch_ends.size()) +
      " batches of at most " + std::to_string(kBenchBatch));
  evaluate(all); // warm-up
  evaluate_batches(all);
  const std::vector<double> one_thread_results = [&] {
    evaluate(1);
    return results;
  }();
  // 1-thread and all-thread runs alternate; the speed-up is the median of the
  // ratios within each round, so that a slow phase of the machine (another
  // process on the second core) hits both sides of a ratio. The virtual cores of
  // this host do not always run equally fast, for seconds on end, whatever the other
  // core does (bench/README.md, "Tenth session"), and an unpinned
  // 1-thread run stays on one of them: it runs once pinned to each core in turn,
  // and the 1-thread rate is the mean of theirs. The all-thread run is not pinned.
  // At most kMaxHeldCores 1-thread runs per round: each costs a run's time.
  const std::vector<int> cores = all > 1 ? cores_to_pin(std::min(all, kMaxHeldCores)) : std::vector<int>{};
  const std::vector<int> one_thread_cores = cores.empty() ? std::vector<int>{-1} : cores;
  int held_runs = 0, hold_attempts = 0;
  std::vector<double> t1, tn, ratio, ratio_faster, b1, bn, batch_ratio, host_ratio, spread;
  // Times one run (run() returns its seconds) and records it with the steal time
  // accounted meanwhile.
  auto record = [&](int round, const char* work, int threads, int core, const std::function<double()>& run) {
    const double steal_before = steal_ms();
    const double seconds = run();
    const double steal_after = steal_before < 0.0 ? -1.0 : steal_ms();
    report.population_runs.push_back(
        {round, work, threads, core, seconds, steal_after < 0.0 ? -1.0 : steal_after - steal_before});
    return seconds;
  };
  // Control items timed in the same rounds: 1-thread time / all-thread time of
  // items that share nothing; their values stay observable in `out`.
  auto control_speedup = [&](int round, const char* work, std::vector<double>& out,
                             const std::function<double(std::size_t)>& item) {
    auto timed = [&](int threads) {
      return record(round, work, threads, -1, [&] {
        const auto t0 = Clock::now();
        parallel_for_index(out.size(), threads, [&](std::size_t i) { out[i] = item(i); });
        return seconds_since(t0);
      });
    };
    const double one = timed(1);
    return one / timed(all);
  };
  // One population round of `work`: its 1-thread runs (one per core, the first
  // core alternating from round to round so that neither always runs first) and
  // its all-thread run (none with one thread only).
  auto population_round = [&](int round, const char* work, const std::function<double(int)>& evaluate_on) {
    std::vector<double> per_core;
    const std::size_t n = one_thread_cores.size();
    for (std::size_t k = 0; k < n; ++k) {
      const int core = one_thread_cores[(k + static_cast<std::size_t>(round)) % n];
      const CoreHold hold(core);
      if (core >= 0) ++hold_attempts;
      if (hold.held()) ++held_runs;
      per_core.push_back(record(round, work, 1, hold.held() ? core : -1, [&] { return evaluate_on(1); }));
    }
    const double all_seconds = all > 1 ? record(round, work, all, -1, [&] { return evaluate_on(all); }) : per_core.front();
    return std::pair{per_core, all_seconds};
  };
  std::vector<double> arithmetic(count), divider_ratio;
  // Square-root/divide-bound items: about 25 ms on one thread.
  std::vector<double> divider(std::max<std::size_t>(count, 2));
  const soda::SimdLevel level = soda::best_simd_level();
  const int population_runs = in.options.quick ? in.runs : 31;
  for (int r = 0; r < population_runs; ++r) {
    if (all > 1) {
      host_ratio.push_back(control_speedup(r, "arithmetic", arithmetic, arithmetic_item));
      divider_ratio.push_back(
          control_speedup(r, "divider", divider, [level](std::size_t i) { return divider_item(i, level); }));
    }
    const auto [fast_cores, fast_all] = population_round(r, "fast", evaluate);
    t1.push_back(at_mean_rate(fast_cores));
    tn.push_back(fast_all);
    ratio.push_back(t1.back() / tn.back());
    const double faster = *std::min_element(fast_cores.begin(), fast_cores.end());
    ratio_faster.push_back(faster / tn.back());
    spread.push_back(*std::max_element(fast_cores.begin(), fast_cores.end()) / faster);
    const auto [batch_cores, batch_all] = population_round(r, "fast-batch", evaluate_batches);
    b1.push_back(at_mean_rate(batch_cores));
    bn.push_back(batch_all);
    batch_ratio.push_back(b1.back() / bn.back());
  }
  if (results != one_thread_results) throw std::runtime_error("population results depend on the thread count");
  if (batch_results != one_thread_results) throw std::runtime_error("batch results differ from one by one");
  for (const char* engine : {"fast", "fast-batch"}) {
    const bool batch = std::string(engine) == "fast-batch";
    for (int threads : {1, all}) {
      SpeedRow row;
      row.section = "population";
      row.creature = std::to_string(count) + " creatures";
      row.engine = engine;
      row.batch = batch ? kBenchBatch : 1;
      row.threads = threads;
      row.links = static_cast<int>(links_per_round / static_cast<long long>(count));
      row.frames = frames;
      row.runs = population_runs;
      row.median_seconds = median(threads == 1 ? (batch ? b1 : t1) : (batch ? bn : tn));
      row.frames_per_second = static_cast<double>(count) * frames / row.median_seconds;
      row.link_updates_per_second = static_cast<double>(links_per_round) * frames / row.median_seconds;
      report.rows.push_back(row);
      if (all == 1) break;
    }
  }
  report.population_speedup = all == 1 ? 1.0 : median(ratio);
  report.population_batch_speedup = all == 1 ? 1.0 : median(batch_ratio);
  report.population_speedup_vs_faster_core = all == 1 ? 1.0 : median(ratio_faster);
  report.core_speed_spread = median(spread);
  report.pinned_cores = hold_attempts > 0 && held_runs == hold_attempts ? static_cast<int>(cores.size()) : 0;
  std::vector<double> one_thread_runs;
  for (const PopulationRun& run : report.population_runs) {
    if (run.work == "fast" && run.threads == 1) one_thread_runs.push_back(run.seconds);
  }
  report.one_thread_run_seconds = median(one_thread_runs);
  report.host_speedup = all == 1 ? 1.0 : median(host_ratio);
  report.host_divider_speedup = all == 1 ? 1.0 : median(divider_ratio);
  report.population_rounds = population_runs;
  report.shared_core_rounds =
      static_cast<int>(std::count_if(divider_ratio.begin(), divider_ratio.end(), [](double v) { return v < kSharedCoreBelow; }));
  // The same medians over the rounds where the divider-bound items said two
  // physical cores, and the rounds whose ratio is above what `all` threads can
  // give (their runs saw different host states).
  std::vector<double> two_core_fast, two_core_batch;
  for (std::size_t r = 0; r < divider_ratio.size(); ++r) {
    if (divider_ratio[r] < kSharedCoreBelow) continue;
    two_core_fast.push_back(ratio[r]);
    two_core_batch.push_back(batch_ratio[r]);
  }
  report.population_speedup_two_cores = median(two_core_fast);
  report.population_batch_speedup_two_cores = median(two_core_batch);
  report.above_ideal_rounds = static_cast<int>(
      std::count_if(ratio.begin(), ratio.end(), [&](double v) { return v > kAboveIdeal * static_cast<double>(all); }));
  for (const std::vector<double>* values : {&arithmetic, &divider}) {
    for (double v : *values) {
      if (!std::isfinite(v)) throw std::runtime_error("a control work item gave a non-finite value");
    }
  }
  if (all == 1) {
    in.say("population on 1 thread only (--threads 1): no speed-up to report");
    return;
  }
  in.say("population speed-up on " + std::to_string(all) + " threads: " + fmt("%.2f", report.population_speedup) +
      " one by one, " + fmt("%.2f", report.population_batch_speedup) +
      " in batches (one by one against the faster core: " + fmt("%.2f", report.population_speedup_vs_faster_core) +
      "; the cores' 1-thread times differed by " + fmt("%.2f", report.core_speed_spread) +
      "x); items that share nothing, in the same rounds: " +
      fmt("%.2f", report.host_speedup) + " (latency-bound), " + fmt("%.2f", report.host_divider_speedup) +
      " (square-root/divide-bound; below " + fmt("%.1f", kSharedCoreBelow) + " in " +
      std::to_string(report.shared_core_rounds) + " of " + std::to_string(report.population_rounds) + " rounds)");
}

} // namespace sodaevo::bench
