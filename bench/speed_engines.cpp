#include "bench/speed_engines.hpp"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "bench/baselines.hpp"
#include "bench/median.hpp"
#include "core/batch_step.hpp"
#include "core/fast_step.hpp"
#include "core/scene_analysis.hpp"
#include "core/step.hpp"
#include "evolve/evaluators/evaluator.hpp"

namespace sodaevo::bench {

namespace {
std::atomic<bool> g_cpu_clock{false};
} // namespace

void time_engines_by_cpu(bool on) { g_cpu_clock = on; }

double engine_clock() {
  if (!g_cpu_clock) return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

namespace {

// Keeps results observable so the optimiser cannot drop a run.
volatile double g_sink = 0.0;

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

/// Frames for one run of about `target` seconds (at least 1). The time per frame
/// is the slope between the last two trial runs (4x the frames), not the last
/// run's time over its frames: a run also has a fixed cost (making its states,
/// loading them into the stepper) that would otherwise count as frames, and an
/// engine with many states per frame (fast-replicas) got a handful of frames, its
/// timed runs mostly that fixed cost. At most 20x the frames of the plain quotient.
long long calibrate(const Engine& e, double target) {
  long long frames = 1, last_frames = 0;
  double last = 0.0;
  for (;;) {
    if (e.prepare) e.prepare();
    const double t0 = engine_clock();
    e.run(frames);
    const double t = engine_clock() - t0;
    if ((t >= target * 0.25 && last_frames > 0) || frames >= (1LL << 40)) {
      const double quotient = t / static_cast<double>(frames);
      double per_frame = quotient;
      if (last_frames > 0 && t > last) per_frame = (t - last) / static_cast<double>(frames - last_frames);
      per_frame = std::clamp(per_frame, quotient / 20.0, quotient);
      return std::max<long long>(1, static_cast<long long>(target / std::max(per_frame, 1e-12)));
    }
    last = t;
    last_frames = frames;
    frames *= 4;
  }
}

} // namespace

soda::Model shifted_copy(const soda::Model& model, int k) {
  soda::Model m = model;
  for (std::size_t i = 0; i < m.link_phase.size(); ++i) {
    if (m.link_muscle[i]) m.link_phase[i] = soda::wrap_phase(m.link_phase[i] + 0.0007 * k);
  }
  return m;
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
    // AVX2 or AVX-512 (lockstep_batch.hpp); "fast-batch-fused" the same 16 fused
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
  // fast-batch and fast-replicas start each run from copies of the initial
  // states made once, copied before the run and not timed (Engine::prepare): the
  // GA makes a state once per rollout of thousands of frames, and a timed run
  // here is tens to hundreds of frames (fast-replicas steps 8 times as many
  // states), so making them in the run would weigh on fast-replicas 8 times as
  // much as on fast-batch. Loading the states into the steppers is timed.
  auto start = std::make_shared<std::vector<soda::State>>();
  for (const soda::Model& m : *models) start->push_back(soda::make_state(m));
  auto work = std::make_shared<std::vector<soda::State>>();
  engines.push_back({"fast-batch",
                     [batches, work, ends](long long frames) {
                       for (std::size_t b = 0; b < batches->size(); ++b) {
                         std::vector<soda::State*> sp;
                         for (std::size_t k = (*batches)[b].first; k < ends[b]; ++k) sp.push_back(&(*work)[k]);
                         (*batches)[b].second->run(sp, frames);
                       }
                       g_sink = g_sink + work->back().x[0];
                     },
                     count, [start, work] { *work = *start; }});
  // "fast-replicas": each creature as the GA's estimator sees it, kReplicas
  // states of its one Model (replica 0 exact, r jittered with seed r), in the
  // batches the GA's evaluation cuts (the fast-batch batches, each creature's
  // replicas one after the other, as evolve/estimators/replica_estimator.cpp orders its
  // rollouts): one BatchStepper per batch, told which states carry jitter, as
  // the walk problem builds it (lockstep lanes where the CPU has AVX2 or AVX-512). Counted
  // in replica-frames (issue 26 item 4: against fast-batch's creature-frames).
  constexpr int kReplicas = 8;
  auto replicas = std::make_shared<std::vector<std::unique_ptr<soda::BatchStepper>>>();
  for (std::size_t b = 0, first = 0; b < ends.size(); first = ends[b], ++b) {
    std::vector<const soda::Model*> ptrs;
    std::vector<bool> jittered;
    for (std::size_t k = first; k < ends[b]; ++k) {
      for (int r = 0; r < kReplicas; ++r) {
        ptrs.push_back(&(*models)[k]);
        jittered.push_back(r != 0);
      }
    }
    replicas->push_back(std::make_unique<soda::BatchStepper>(ptrs, 1'000'000, soda::FastStepOptions{}, jittered));
  }
  auto replica_start = std::make_shared<std::vector<soda::State>>();
  for (const soda::Model& m : *models) {
    for (int r = 0; r < kReplicas; ++r) {
      replica_start->push_back(soda::make_state(m));
      replica_start->back().jitter = {static_cast<std::uint64_t>(r), 0.002};
    }
  }
  auto replica_work = std::make_shared<std::vector<soda::State>>();
  engines.push_back({"fast-replicas",
                     [replicas, replica_work, ends](long long frames) {
                       std::vector<soda::State*> sp;
                       for (std::size_t b = 0, first = 0; b < ends.size(); first = ends[b], ++b) {
                         sp.clear();
                         for (std::size_t k = first * kReplicas; k < ends[b] * kReplicas; ++k) sp.push_back(&(*replica_work)[k]);
                         (*replicas)[b]->run(sp, frames);
                       }
                       g_sink = g_sink + replica_work->back().x[0];
                     },
                     count * kReplicas, [replica_start, replica_work] { *replica_work = *replica_start; }});
  return engines;
}

Size size_of(const soda::Model& model) { return {model.mass_count, static_cast<double>(model.link_count())}; }

std::vector<SpeedRow> time_engines(const std::string& section, const std::string& creature, Size size,
                                   std::vector<Engine> engines, int runs, double target) {
  std::vector<long long> frames;
  for (const Engine& e : engines) {
    const long long warm_up = std::max<long long>(1, calibrate(e, target / 8));
    if (e.prepare) e.prepare();
    e.run(warm_up);
    frames.push_back(calibrate(e, target));
  }
  std::vector<std::vector<double>> times(engines.size());
  for (int r = 0; r < runs; ++r) {
    for (std::size_t i = 0; i < engines.size(); ++i) {
      if (engines[i].prepare) engines[i].prepare();
      const double t0 = engine_clock();
      engines[i].run(frames[i]);
      times[i].push_back(engine_clock() - t0);
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
  // Issue 26's speed target: the replicas against the GA's batch in the same rounds.
  if (const std::size_t replicas = index_of("fast-replicas"); replicas != engines.size()) {
    rows[replicas].speedup_vs_batch = ratio_to(index_of("fast-batch"), replicas);
  }
  return rows;
}

} // namespace sodaevo::bench
