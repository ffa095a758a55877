#include "bench/speed_bench.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "bench/baselines.hpp"
#include "bench/median.hpp"
#include "bench/synthetic.hpp"
#include "core/batch_step.hpp"
#include "core/fast_step.hpp"
#include "core/model.hpp"
#include "core/number_text.hpp"
#include "core/scene_analysis.hpp"
#include "core/simd_level.hpp"
#include "core/detail/simd_ops.hpp"
#include "core/step.hpp"
#include "evolve/evaluator.hpp"
#include "evolve/parallel_for.hpp"
#include "evolve/run_config.hpp"
#include "evolve/run_reader.hpp"
#include "evolve/walk_problem.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::bench {

namespace {

/// A work item that shares nothing with the others: products and sums on 16
/// independent chains (no memory traffic), about a millisecond. Each chain waits on
/// its own latency, so its thread speed-up shows whether a second thread runs at
/// all (a host may time-slice both virtual cores on one hardware thread), not
/// whether the two share one physical core's units: divider_item below shows that.
double arithmetic_item(std::size_t i) {
  double acc[16];
  for (int k = 0; k < 16; ++k) acc[k] = 1.0 + static_cast<double>((i + k) % 7);
  for (int pass = 0; pass < 400000; ++pass) {
    for (double& a : acc) a = a * 0.9999999 + 1e-7;
  }
  double sum = 0.0;
  for (double a : acc) sum += a;
  return sum;
}

/// A work item bound by the square-root/divide unit, as the step's link pass is:
/// four square roots and four divisions per pass on independent vectors of the
/// engine's SIMD level, about half a millisecond. Its thread speed-up is 2x only
/// on two physical cores. Where the host runs the two virtual cores as the two
/// hardware threads of one physical core, they share that unit and it drops to 1x,
/// while the arithmetic items above (chains waiting on their own latency) still
/// show 2x. Measured on this machine: 1.00x and 2.00x in the same rounds, at times.
// GCC 12 takes the undefined pass-through operand of _mm512_sqrt_pd for an
// uninitialised variable once it is inlined here: a false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class O>
double divider_passes(std::size_t i) {
  using V = typename O::V;
  V v[8];
  for (int k = 0; k < 8; ++k) v[k] = O::set1(2.5 + static_cast<double>((i + static_cast<std::size_t>(k)) % 7));
  const V shift = O::set1(1.5), divisor = O::set1(1.0000001);
  for (int pass = 0; pass < 40000; ++pass) {
    for (int k = 0; k < 4; ++k) v[k] = O::sqrt(O::add(v[k], shift)); // stays near 1.8
    for (int k = 4; k < 8; ++k) v[k] = O::div(v[k], divisor);
  }
  double lanes[soda::simd::kMaxWidth] = {};
  double sum = 0.0;
  for (const V& x : v) {
    O::storeu(lanes, x);
    sum += lanes[0];
  }
  return sum;
}
// Compiled for each instruction set (called only where the CPU has it), as
// core/exact_sines.cpp does.
#pragma GCC push_options
#pragma GCC target("avx2,fma")
template double divider_passes<soda::simd::Avx2Ops>(std::size_t);
double divider_avx2(std::size_t i) { return divider_passes<soda::simd::Avx2Ops>(i); }
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx512f")
template double divider_passes<soda::simd::Avx512Ops>(std::size_t);
double divider_avx512(std::size_t i) { return divider_passes<soda::simd::Avx512Ops>(i); }
#pragma GCC pop_options
#pragma GCC diagnostic pop

double divider_item(std::size_t i, soda::SimdLevel level) {
  switch (level) {
    case soda::SimdLevel::Avx512: return divider_avx512(i);
    case soda::SimdLevel::Avx2: return divider_avx2(i);
    default: return divider_passes<soda::simd::Sse2Ops>(i);
  }
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The first `wanted` cores this process may run on; empty where there are fewer or
/// the set cannot be read (the 1-thread runs then go unpinned). The all-thread run
/// may use other cores where more are allowed than `wanted`.
std::vector<int> cores_to_pin(int wanted) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return {};
  std::vector<int> cores;
  for (int c = 0; c < CPU_SETSIZE && static_cast<int>(cores.size()) < wanted; ++c) {
    if (CPU_ISSET(c, &set)) cores.push_back(c);
  }
  if (static_cast<int>(cores.size()) < wanted) return {};
  return cores;
}

/// Holds the calling thread to one core while it lives and puts the thread's
/// previous core set back. `held()` says whether the hold took (it may not, where
/// the process may not choose its cores); a thread started meanwhile would inherit
/// the hold, so the population's 1-thread runs start none.
class CoreHold {
 public:
  explicit CoreHold(int core) {
    if (core < 0 || sched_getaffinity(0, sizeof saved_, &saved_) != 0) return;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(core, &one);
    held_ = sched_setaffinity(0, sizeof one, &one) == 0;
  }
  ~CoreHold() noexcept(false) {
    // Failing to let go would leave every later thread on one core, and the
    // all-thread figures wrong without a word.
    if (held_ && sched_setaffinity(0, sizeof saved_, &saved_) != 0 && std::uncaught_exceptions() == 0) {
      throw std::runtime_error("bench speed: could not release the 1-thread run's hold on its core");
    }
  }
  CoreHold(const CoreHold&) = delete;
  CoreHold& operator=(const CoreHold&) = delete;
  bool held() const { return held_; }

 private:
  cpu_set_t saved_{};
  bool held_ = false;
};

/// Steal time the kernel has accounted to this machine's virtual CPUs since boot,
/// summed over them, in ms (the "steal" column of /proc/stat's cpu line: time the
/// hypervisor ran something else while a virtual CPU had work), or -1 where it
/// cannot be read. Counted in clock ticks (10 ms here).
double steal_ms() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  long long value[8];
  if (!(stat >> cpu) || cpu != "cpu") return -1.0;
  for (long long& v : value) {
    if (!(stat >> v)) return -1.0;
  }
  const long ticks_per_second = sysconf(_SC_CLK_TCK);
  return ticks_per_second > 0 ? static_cast<double>(value[7]) * 1000.0 / static_cast<double>(ticks_per_second) : -1.0;
}

/// The time a run would take at the mean of the rates of `per_core` runs.
double at_mean_rate(const std::vector<double>& per_core) {
  double rate = 0.0;
  for (double t : per_core) rate += 1.0 / t;
  return static_cast<double>(per_core.size()) / rate;
}

// Keeps results observable so the optimiser cannot drop a run.
volatile double g_sink = 0.0;

/// Copy k of `model` with every muscle phase moved by k * 0.0007 cycles: as costly
/// to step as the model, but its sine arguments are its own. Fused scenes compute
/// a sine shared by creatures with the same wave and muscle phase once
/// (core/fused/sine_rows.cpp, fill_rows), so identical copies would overstate what a batch of
/// different creatures gets.
soda::Model shifted_copy(const soda::Model& model, int k) {
  soda::Model m = model;
  for (std::size_t i = 0; i < m.link_phase.size(); ++i) {
    if (m.link_muscle[i]) m.link_phase[i] = soda::wrap_phase(m.link_phase[i] + 0.0007 * k);
  }
  return m;
}

/// An engine under test: run(frames) steps from the initial state.
struct Engine {
  std::string name;
  std::function<void(long long)> run;
  int creatures = 1; ///< creatures one run steps (each by `frames`)
};

/// Which engines besides seed, plain, fast-sse2 and fast.
struct EngineChoice {
  bool reference = false;
  bool batch = false;   ///< fast-batch, fast-batch-fused, fast-batch-same
  bool no_wave = false; ///< fast-no-wave (creatures whose muscles need the wave)
};

/// An engine that steps each of `models` in turn from its initial state with its
/// own stepper (PlainLoop, FastStepper: run(State&, frames)).
template <class Stepper>
Engine each_in_turn(const char* name, std::shared_ptr<const std::vector<soda::Model>> models,
                    std::shared_ptr<std::vector<std::unique_ptr<Stepper>>> steppers) {
  return {name,
          [steppers, models](long long frames) {
            for (std::size_t k = 0; k < steppers->size(); ++k) {
              soda::State s = soda::make_state((*models)[k]);
              (*steppers)[k]->run(s, frames);
              g_sink = g_sink + s.x[0];
            }
          },
          static_cast<int>(models->size())};
}

/// The seed baseline and the plain loop stepping `models` one after the other (a
/// population as those programs evaluate it), named `seed_name` and `plain_name`.
std::vector<Engine> sequential_baselines(std::shared_ptr<const std::vector<soda::Model>> models,
                                         const char* seed_name, const char* plain_name) {
  const int count = static_cast<int>(models->size());
  auto seeds = std::make_shared<std::vector<std::unique_ptr<SeedBaseline>>>();
  auto plains = std::make_shared<std::vector<std::unique_ptr<PlainLoop>>>();
  for (const soda::Model& m : *models) {
    seeds->push_back(std::make_unique<SeedBaseline>(m));
    plains->push_back(std::make_unique<PlainLoop>(m));
  }
  std::vector<Engine> engines;
  engines.push_back({seed_name,
                     [seeds, models](long long frames) {
                       for (auto& s : *seeds) {
                         s->reset();
                         s->run(frames);
                         g_sink = g_sink + s->checksum();
                       }
                     },
                     count});
  engines.push_back(each_in_turn(plain_name, models, plains));
  return engines;
}

std::vector<Engine> make_engines(const soda::Model& model, const EngineChoice& choice) {
  std::vector<Engine> engines;
  auto seed = std::make_shared<SeedBaseline>(model);
  engines.push_back({"seed", [seed](long long frames) {
                       seed->reset();
                       seed->run(frames);
                       g_sink = g_sink + seed->checksum();
                     }});
  auto plain = std::make_shared<PlainLoop>(model);
  engines.push_back({"plain", [plain, &model](long long frames) {
                       soda::State s = soda::make_state(model);
                       plain->run(s, frames);
                       g_sink = g_sink + s.x[0];
                     }});
  if (choice.reference) {
    engines.push_back({"reference", [&model](long long frames) {
                         soda::State s = soda::make_state(model);
                         soda::run(model, s, frames);
                         g_sink = g_sink + s.x[0];
                       }});
  }
  for (soda::SimdLevel level : {soda::SimdLevel::Sse2, soda::SimdLevel::Auto}) {
    soda::FastStepOptions opt;
    opt.simd = level;
    auto stepper = std::make_shared<soda::FastStepper>(model, 1'000'000, opt);
    engines.push_back({level == soda::SimdLevel::Sse2 ? "fast-sse2" : "fast", [stepper, &model](long long frames) {
                         soda::State s = soda::make_state(model);
                         stepper->run(s, frames);
                         g_sink = g_sink + s.x[0];
                       }});
  }
  // "fast-no-wave": the same creature with its wave amplitude at 0, so no sines
  // (its muscles hold their rest lengths). Not this creature's motion: one frame
  // of it is the same dependent chain (the same links, masses and walls) without
  // the sines, which is what one creature alone would cost if its sines were
  // free (speed.md's bound on one creature alone).
  if (choice.no_wave && soda::analyse_scene(model, 1).wave) {
    auto still = std::make_shared<soda::Model>(model);
    still->wave_amplitude = 0.0;
    soda::set_constants(*still); // its muscles' power Aw*Am is now 0
    auto stepper = std::make_shared<soda::FastStepper>(*still, 1'000'000);
    engines.push_back({"fast-no-wave", [stepper, still](long long frames) {
                         soda::State s = soda::make_state(*still);
                         stepper->run(s, frames);
                         g_sink = g_sink + s.x[0];
                       }});
  }
  if (choice.batch) {
    // The baselines on the same kBenchBatch creatures as the batched engines below,
    // one after the other on one core (a population as a seed or plain program
    // evaluates it): the batched engines' ratios are taken against these, so that
    // both sides of a ratio step the same creatures (time_engines).
    auto shifted = std::make_shared<std::vector<soda::Model>>();
    for (int k = 0; k < kBenchBatch; ++k) shifted->push_back(shifted_copy(model, k));
    for (Engine& e : sequential_baselines(shifted, "seed-batch", "plain-batch")) engines.push_back(std::move(e));
    // kBenchBatch creatures on one core (population throughput), as
    // soda::BatchStepper steps them: "fast-batch" 16 different ones (shifted_copy:
    // no sine shared between them), one shape, so in lockstep where the CPU has
    // AVX-512 (lockstep_batch.hpp); "fast-batch-fused" the same 16 fused
    // (lockstep off: the path of a population of mixed shapes); "fast-batch-same"
    // 16 identical copies fused, which share every sine (the fused path's best
    // case: a population sharing genes).
    struct BatchEngine {
      const char* name;
      bool same, lockstep;
    };
    for (const BatchEngine& e : {BatchEngine{"fast-batch", false, true}, BatchEngine{"fast-batch-fused", false, false},
                                 BatchEngine{"fast-batch-same", true, false}}) {
      auto copies = std::make_shared<std::vector<soda::Model>>();
      for (int k = 0; k < kBenchBatch; ++k) copies->push_back(e.same ? model : shifted_copy(model, k));
      std::vector<const soda::Model*> ptrs;
      for (const soda::Model& m : *copies) ptrs.push_back(&m);
      soda::FastStepOptions opt;
      opt.lockstep = e.lockstep;
      auto stepper = std::make_shared<soda::BatchStepper>(ptrs, 1'000'000, opt);
      engines.push_back({e.name,
                         [stepper, copies](long long frames) {
                           std::vector<soda::State> states;
                           for (const soda::Model& m : *copies) states.push_back(soda::make_state(m));
                           std::vector<soda::State*> sp;
                           for (soda::State& s : states) sp.push_back(&s);
                           stepper->run(sp, frames);
                           g_sink = g_sink + states.back().x[0];
                         },
                         kBenchBatch});
    }
  }
  return engines;
}

/// The engines of the GA section, on `models` (the creatures of a saved run as the
/// GA steps them): "seed" and "plain" step them one after the other, "fast" with a
/// FastStepper each, "fast-batch" in the batches the GA's evaluation cuts on one
/// thread (evaluation_batch_size, fused_batch_ends), each a soda::BatchStepper.
std::vector<Engine> make_ga_engines(std::shared_ptr<const std::vector<soda::Model>> models) {
  const int count = static_cast<int>(models->size());
  std::vector<Engine> engines = sequential_baselines(models, "seed", "plain");
  auto fasts = std::make_shared<std::vector<std::unique_ptr<soda::FastStepper>>>();
  for (const soda::Model& m : *models) fasts->push_back(std::make_unique<soda::FastStepper>(m, 1'000'000));
  engines.push_back(each_in_turn("fast", models, fasts));
  std::vector<int> links;
  for (const soda::Model& m : *models) links.push_back(m.link_count());
  const std::vector<std::size_t> ends = soda::fused_batch_ends(links, evaluation_batch_size(models->size(), 1));
  auto batches = std::make_shared<std::vector<std::pair<std::size_t, std::unique_ptr<soda::BatchStepper>>>>();
  for (std::size_t b = 0, first = 0; b < ends.size(); first = ends[b], ++b) {
    std::vector<const soda::Model*> ptrs;
    for (std::size_t k = first; k < ends[b]; ++k) ptrs.push_back(&(*models)[k]);
    batches->emplace_back(first, std::make_unique<soda::BatchStepper>(ptrs, 1'000'000));
  }
  engines.push_back({"fast-batch",
                     [batches, models, ends](long long frames) {
                       std::vector<soda::State> states;
                       for (const soda::Model& m : *models) states.push_back(soda::make_state(m));
                       for (std::size_t b = 0; b < batches->size(); ++b) {
                         std::vector<soda::State*> sp;
                         for (std::size_t k = (*batches)[b].first; k < ends[b]; ++k) sp.push_back(&states[k]);
                         (*batches)[b].second->run(sp, frames);
                       }
                       g_sink = g_sink + states.back().x[0];
                     },
                     count});
  return engines;
}

/// Frames for one run of about `target` seconds (at least 1).
long long calibrate(const Engine& e, double target) {
  long long frames = 1;
  for (;;) {
    const auto t0 = Clock::now();
    e.run(frames);
    const double t = seconds_since(t0);
    if (t >= target * 0.25 || frames >= (1LL << 40)) {
      const double per_frame = t / static_cast<double>(frames);
      return std::max<long long>(1, static_cast<long long>(target / std::max(per_frame, 1e-12)));
    }
    frames *= 4;
  }
}

/// Per creature stepped: the masses and links a row reports; link updates per
/// second are frames per second times `links` (a mean over a set of creatures).
struct Size {
  int masses = 0;
  double links = 0.0;
};

Size size_of(const soda::Model& model) { return {model.mass_count, static_cast<double>(model.link_count())}; }

/// Times every engine on one model (or set of models): calibrated frames,
/// interleaved runs, medians.
std::vector<SpeedRow> time_engines(const std::string& section, const std::string& creature, Size size,
                                   std::vector<Engine> engines, int runs, double target) {
  std::vector<long long> frames;
  for (const Engine& e : engines) {
    e.run(std::max<long long>(1, calibrate(e, target / 8))); // warm-up
    frames.push_back(calibrate(e, target));
  }
  std::vector<std::vector<double>> times(engines.size());
  for (int r = 0; r < runs; ++r) {
    for (std::size_t i = 0; i < engines.size(); ++i) {
      const auto t0 = Clock::now();
      engines[i].run(frames[i]);
      times[i].push_back(seconds_since(t0));
    }
  }
  std::vector<SpeedRow> rows;
  for (std::size_t i = 0; i < engines.size(); ++i) {
    SpeedRow row;
    row.section = section;
    row.creature = creature;
    row.engine = engines[i].name;
    row.batch = engines[i].creatures;
    row.masses = size.masses;
    row.links = static_cast<int>(std::lround(size.links));
    row.frames = frames[i];
    row.runs = runs;
    row.median_seconds = median(times[i]);
    row.frames_per_second = static_cast<double>(frames[i]) * engines[i].creatures / row.median_seconds;
    row.link_updates_per_second = row.frames_per_second * size.links;
    rows.push_back(row);
  }
  // Ratios: the median over the rounds of the ratio within each round (the two
  // runs of a round are a second apart at most), so that a slow phase of the
  // machine, which can last from seconds to minutes here, hits both sides of a
  // ratio instead of one median.
  auto index_of = [&](const std::string& name) {
    std::size_t j = 0;
    while (j < engines.size() && engines[j].name != name) ++j;
    return j; // engines.size(): none
  };
  auto ratio_to = [&](std::size_t b, std::size_t i) {
    if (b == engines.size()) return 0.0;
    std::vector<double> per_round;
    for (int r = 0; r < runs; ++r) {
      const double fps_i = static_cast<double>(frames[i]) * engines[i].creatures / times[i][r];
      const double fps_b = static_cast<double>(frames[b]) * engines[b].creatures / times[b][r];
      per_round.push_back(fps_i / fps_b);
    }
    return median(per_round);
  };
  // An engine that steps a batch is measured against the baselines stepping the
  // same batch (seed-batch, plain-batch) where they ran, else against one creature.
  const std::size_t seed = index_of("seed"), plain = index_of("plain");
  const std::size_t seed_batch = index_of("seed-batch"), plain_batch = index_of("plain-batch");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const bool on_batch = engines[i].creatures > 1 && seed_batch != engines.size() && plain_batch != engines.size();
    rows[i].speedup_vs_seed = ratio_to(on_batch ? seed_batch : seed, i);
    rows[i].speedup_vs_plain = ratio_to(on_batch ? plain_batch : plain, i);
  }
  return rows;
}

std::string fmt(const char* f, double v) { return soda::format_printf(f, v); }

} // namespace

SpeedReport run_speed_bench(const SpeedOptions& options) {
  auto say = [&](const std::string& s) {
    if (options.progress) options.progress(s);
  };
  SpeedReport report;
  report.simd = soda::simd_level_name(soda::best_simd_level());
  const int runs = options.quick ? 3 : 11;
  const double target = options.quick ? 0.02 : 0.12;

  // 1. Bundled creatures.
  std::vector<std::pair<std::string, soda::Model>> creatures;
  for (const auto& [name, path] : options.creatures) {
    creatures.emplace_back(name, soda::build_model(soda::read_model_file(path).def));
  }
  for (const auto& [name, model] : creatures) {
    if (!options.creature_section) break; // the models are still read: the population needs them
    say("creature " + name + " (" + std::to_string(model.mass_count) + " masses, " +
        std::to_string(model.link_count()) + " links)");
    const EngineChoice every{.reference = true, .batch = true, .no_wave = true};
    for (SpeedRow& r : time_engines("creature", name, size_of(model), make_engines(model, every), runs, target)) {
      report.rows.push_back(r);
    }
  }

  // 2. Size sweep.
  const std::vector<int> sizes = options.quick ? std::vector<int>{10, 100, 1000, 10000, 100000}
                                               : std::vector<int>{10, 30, 100, 300, 1000, 3000, 10000, 30000, 100000};
  for (int links : sizes) {
    if (!options.size_section) break;
    const soda::Model model = soda::build_model(synthetic_creature(links));
    say("synthetic " + std::to_string(links) + " links");
    for (SpeedRow& r : time_engines("size", "synthetic", size_of(model), make_engines(model, {}), runs, target)) {
      if (r.engine == "fast" && r.link_updates_per_second > report.best_link_updates_per_second) {
        report.best_link_updates_per_second = r.link_updates_per_second;
        report.best_links = r.links;
      }
      report.rows.push_back(r);
    }
  }

  // 4. The GA's own creatures (run before 3, which may end the bench early): every
  //    creature of the saved generations, prepared as the GA evaluates them.
  if (options.ga_section && !options.ga_run.empty()) {
    const std::filesystem::path run(options.ga_run);
    const RunConfig config = read_run_config(run / "config.json");
    const WalkProblem problem(config);
    std::vector<int> generations = saved_generations(run);
    if (generations.empty()) throw std::runtime_error(options.ga_run + ": the run has no saved generation");
    if (options.quick && generations.size() > 2) generations = {generations.front(), generations.back()};
    auto models = std::make_shared<std::vector<soda::Model>>();
    double links = 0.0;
    for (int g : generations) {
      for (const Individual& individual : read_saved_generation(run, g).individuals) {
        // As the GA's estimator: a creature the problem refuses is not stepped.
        soda::ModelDef prepared;
        try {
          prepared = problem.prepare(individual.creature);
        } catch (const std::exception&) {
          ++report.ga_refused;
          continue;
        }
        models->push_back(soda::build_model(prepared));
        links += models->back().link_count();
      }
    }
    if (models->empty()) throw std::runtime_error(options.ga_run + ": no creature of the saved generations can be stepped");
    report.ga_run = options.ga_run;
    report.ga_generations = static_cast<int>(generations.size());
    report.ga_creatures = static_cast<int>(models->size());
    report.ga_mean_links = links / static_cast<double>(models->size());
    say("the GA's creatures: " + std::to_string(report.ga_creatures) + " from " +
        std::to_string(report.ga_generations) + " saved generations of " + options.ga_run);
    for (SpeedRow& r : time_engines("ga", "ga_run", {0, report.ga_mean_links},
                                    make_ga_engines(models), runs, target)) {
      report.rows.push_back(r);
    }
  }

  // 3. Population throughput: every creature evaluated from scratch (stepper built,
  //    frames run) by index, on 1 thread and on all threads.
  if (!creatures.empty() && options.population_section) {
    const int all = resolve_thread_count(options.threads);
    report.population_threads = all;
    // Short runs (about 50 ms on one thread) in many rounds: this host changes how
    // fast each virtual core runs (what its physical core's other thread does) within
    // a fraction of a second, and a ratio means something only where its two runs saw
    // the same state. Runs of 0.3 s in 9 rounds straddled such changes: their median
    // ratio swung between 1.1x and 1.9x between invocations, while 31 rounds of 50 ms
    // runs gave 1.93-1.97x in five invocations where the host put the two virtual
    // cores on one physical core in at most 8 rounds (bench/README.md, Results).
    // 16 copies of each bundled creature per two threads (48 creatures on this
    // machine): about 50 ms on one thread, and enough batch items to keep every
    // thread busy.
    const int copies = (options.quick ? 4 : 16) * std::max(1, all / 2);
    const long long frames = options.quick ? 1000 : 5000;
    const std::size_t count = creatures.size() * static_cast<std::size_t>(copies);
    // Creature i is copy i / 3 of bundled creature i % 3, its muscle phases shifted
    // (shifted_copy) so that no two creatures share a sine.
    std::vector<soda::Model> population;
    for (std::size_t i = 0; i < count; ++i) {
      population.push_back(shifted_copy(creatures[i % creatures.size()].second, static_cast<int>(i / creatures.size())));
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
    // The batch path (the GA's, ThreadEvaluator in evolve/evaluator.cpp): each work item is a
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
    say("population of " + std::to_string(count) + " creatures x " + std::to_string(frames) + " frames, 1 and " +
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
    // this host do not run equally fast (at times one ran the step 1.6x slower than
    // the other for seconds on end, whatever the other core did), and an unpinned
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
    const int population_runs = options.quick ? runs : 31;
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
      say("population on 1 thread only (--threads 1): no speed-up to report");
      return report;
    }
    say("population speed-up on " + std::to_string(all) + " threads: " + fmt("%.2f", report.population_speedup) +
        " one by one, " + fmt("%.2f", report.population_batch_speedup) +
        " in batches (one by one against the faster core: " + fmt("%.2f", report.population_speedup_vs_faster_core) +
        "; the cores' 1-thread times differed by " + fmt("%.2f", report.core_speed_spread) +
        "x); items that share nothing, in the same rounds: " +
        fmt("%.2f", report.host_speedup) + " (latency-bound), " + fmt("%.2f", report.host_divider_speedup) +
        " (square-root/divide-bound; below " + fmt("%.1f", kSharedCoreBelow) + " in " +
        std::to_string(report.shared_core_rounds) + " of " + std::to_string(report.population_rounds) + " rounds)");
  }
  return report;
}

} // namespace sodaevo::bench
