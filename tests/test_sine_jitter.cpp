// Sine jitter (core/sine_jitter.hpp): the hash as documented, the share of moved
// sines, purity, and a jittered replica in the reference, continuous and fast
// steppers.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/batch_step.hpp"
#include "core/continuous_step.hpp"
#include "core/fast_step.hpp"
#include "core/fused/fused_scene.hpp"
#include "core/lockstep_batch.hpp"
#include "core/model.hpp"
#include "core/sine_jitter.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

namespace {

using sodaevo::test::compare_states;
using sodaevo::test::load_scene;
using sodaevo::test::models_dir;
using sodaevo::test::same_bits;

/// The hash of interfaces.md written out again from its description, as a
/// reference: h = mix64(bits(x) ^ mix64(seed)), splitmix64's finaliser; a hit iff
/// (h >> 11) < floor(p * 2^53); +1 iff h is odd.
int documented_steps(double x, std::uint64_t seed, double p) {
  auto mix = [](std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  if (seed == 0) return 0;
  const std::uint64_t h = mix(std::bit_cast<std::uint64_t>(x) ^ mix(seed));
  const auto threshold = static_cast<std::uint64_t>(std::ldexp(p, 53));
  if ((h >> 11) >= threshold) return 0;
  return (h & 1) != 0 ? 1 : -1;
}

std::vector<double> muscle_arguments(int n) {
  std::vector<double> args;
  std::uint64_t s = 2026;
  for (int i = 0; i < n; ++i) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    args.push_back(soda::kTwoPi * (static_cast<double>(s >> 11) * 0x1p-53 - 0.5));
  }
  return args;
}

} // namespace

TEST_CASE("sine jitter follows the documented hash, and seed 0 moves nothing", "[sine_jitter]") {
  const std::vector<double> args = muscle_arguments(200'000);
  for (std::uint64_t seed : {0ULL, 1ULL, 7ULL, 0xdeadbeefULL}) {
    for (double p : {0.0, 0.002, 0.3, 1.0}) {
      const soda::SineJitter j{seed, p};
      int bad = 0;
      for (double x : args) bad += soda::jitter_steps(x, j) == documented_steps(x, seed, p) ? 0 : 1;
      INFO("seed " << seed << ", p " << p);
      CHECK(bad == 0);
    }
  }
  // A move is one ulp toward +inf or -inf, nothing else.
  const soda::SineJitter all{3, 1.0};
  for (double x : {0.5, -2.0, 3.0, 1e-3}) {
    const double s = std::sin(x);
    const double moved = soda::jittered(s, x, all);
    CHECK(same_bits(moved, std::nextafter(s, soda::jitter_steps(x, all) > 0 ? HUGE_VAL : -HUGE_VAL)));
    CHECK(same_bits(soda::jittered(s, x, soda::SineJitter{0, 1.0}), s));
  }
}

TEST_CASE("the share of jittered sines over 1e6 arguments is close to p", "[sine_jitter]") {
  const std::vector<double> args = muscle_arguments(1'000'000);
  for (double p : {0.002, 0.05}) {
    const soda::SineJitter j{11, p};
    long up = 0, down = 0;
    for (double x : args) {
      const int k = soda::jitter_steps(x, j);
      up += k > 0;
      down += k < 0;
    }
    // Binomial(n, p): hits within 5 standard deviations of n p, and the two
    // directions within 5 standard deviations of half the hits each.
    const double n = static_cast<double>(args.size());
    const double hits = static_cast<double>(up + down);
    INFO("p " << p << ": " << up << " up, " << down << " down");
    CHECK(std::fabs(hits - n * p) < 5.0 * std::sqrt(n * p * (1.0 - p)));
    CHECK(std::fabs(static_cast<double>(up - down)) < 5.0 * std::sqrt(hits));
  }
}

TEST_CASE("sine jitter is a pure function of the argument and the seed", "[sine_jitter]") {
  const std::vector<double> args = muscle_arguments(100'000);
  const soda::SineJitter j{5, 0.01};
  std::vector<int> forward, backward(args.size());
  for (double x : args) forward.push_back(soda::jitter_steps(x, j));
  for (std::size_t i = args.size(); i-- > 0;) backward[i] = soda::jitter_steps(args[i], j);
  CHECK(forward == backward);
  // Another seed moves other arguments.
  int differ = 0;
  for (std::size_t i = 0; i < args.size(); ++i) differ += soda::jitter_steps(args[i], {6, 0.01}) != forward[i];
  CHECK(differ > 1000);
}

TEST_CASE("a jittered walker is deterministic and leaves the exact run", "[sine_jitter]") {
  const auto scene = load_scene(models_dir() / "dainty_walker.xml");
  const soda::Model& m = scene.model;
  auto run = [&](std::uint64_t seed, int frames) {
    soda::State s = soda::make_state(m);
    s.jitter = {seed, 0.002};
    soda::run(m, s, frames);
    return s;
  };
  const soda::State exact = run(0, 3000);
  const soda::State a = run(1, 3000), again = run(1, 3000), b = run(2, 3000);
  CHECK(compare_states(m, a, again).empty());
  CHECK_FALSE(compare_states(m, a, exact).empty());
  CHECK_FALSE(compare_states(m, a, b).empty());
  // Seed 0 is the engine as it was: an explicit exact jitter changes nothing.
  soda::State explicit_exact = soda::make_state(m);
  explicit_exact.jitter = {0, 1.0};
  soda::run(m, explicit_exact, 3000);
  CHECK(compare_states(m, explicit_exact, exact).empty());

  // The continuous mode's Euler at one step per frame is the reference step,
  // jitter included.
  soda::State continuous = soda::make_state(m);
  continuous.jitter = {1, 0.002};
  soda::ContinuousStepper(m, {soda::Integrator::Euler, 1}).run(continuous, 3000);
  CHECK(compare_states(m, continuous, a).empty());
  soda::State rk4_exact = soda::make_state(m), rk4_jittered = soda::make_state(m);
  rk4_jittered.jitter = {1, 0.05};
  soda::ContinuousStepper(m, {soda::Integrator::Rk4, 2}).run(rk4_exact, 2000);
  soda::ContinuousStepper(m, {soda::Integrator::Rk4, 2}).run(rk4_jittered, 2000);
  CHECK_FALSE(compare_states(m, rk4_exact, rk4_jittered).empty());
}

TEST_CASE("jittered states in FastStepper, fused scenes and BatchStepper equal the reference step", "[sine_jitter]") {
  const std::vector<std::string> names = {"dainty_walker.xml", "carefulslug.xml", "monster_truck.xml", "wodka_m1.xml"};
  std::vector<sodaevo::test::Scene> scenes;
  scenes.reserve(names.size());
  for (const std::string& name : names) scenes.push_back(load_scene(models_dir() / name));
  const long long frames = 1500;
  bool moved = false; // some jitter changed a trajectory: the comparisons below can fail
  auto reference = [&](const soda::Model& m, soda::SineJitter jitter, long long n) {
    soda::State s = soda::make_state(m);
    s.jitter = jitter;
    soda::run(m, s, n);
    return s;
  };
  soda::FastStepOptions sse2, ordered, fused_only;
  sse2.simd = soda::SimdLevel::Sse2;
  ordered.force_ordered = true;
  fused_only.lockstep = false;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const soda::Model& m = scenes[k].model;
    const soda::State exact = reference(m, {}, frames);
    for (const soda::FastStepOptions& options : {soda::FastStepOptions{}, sse2, ordered}) {
      INFO(names[k] << ", simd " << static_cast<int>(options.simd) << ", ordered "
                                          << options.force_ordered);
      const soda::SineJitter jitter{3, 0.05};
      const soda::State expected = reference(m, jitter, frames);
      moved = moved || !compare_states(m, expected, exact).empty();
      soda::FastStepper fast(m, frames, options);
      soda::State a = soda::make_state(m);
      a.jitter = jitter;
      fast.run(a, 700);
      fast.run(a, frames - 700);
      CHECK(compare_states(m, expected, a).empty());
      // The same stepper given another replica whose wave is where the last one's
      // was: its rows of sines and targets are made again for its own jitter.
      const soda::SineJitter other{4, 0.05};
      soda::State b = reference(m, other, 700), b_expected = reference(m, other, frames);
      fast.run(b, frames - 700);
      CHECK(compare_states(m, b_expected, b).empty());
      // And back to the exact engine.
      soda::State c = reference(m, {}, 700);
      fast.run(c, frames - 700);
      CHECK(compare_states(m, exact, c).empty());
    }
  }
  // One fused scene of several creatures, exact and jittered, two replicas of one
  // model with the same jitter (they share a wave state) and one with another.
  const std::vector<const soda::Model*> models = {&scenes[0].model, &scenes[1].model, &scenes[0].model,
                                                  &scenes[2].model, &scenes[0].model};
  const std::vector<soda::SineJitter> jitters = {{5, 0.05}, {0, 0.002}, {5, 0.05}, {6, 0.002}, {7, 0.05}};
  std::vector<soda::State> states;
  for (std::size_t i = 0; i < models.size(); ++i) {
    states.push_back(soda::make_state(*models[i]));
    states.back().jitter = jitters[i];
  }
  std::vector<soda::State> batch_states = states;
  std::vector<soda::State*> pointers, batch_pointers;
  for (std::size_t i = 0; i < states.size(); ++i) {
    pointers.push_back(&states[i]);
    batch_pointers.push_back(&batch_states[i]);
  }
  soda::FusedScene scene(models, frames);
  scene.run(pointers.data(), 900);
  scene.run(pointers.data(), frames - 900);
  soda::BatchStepper batch(models, frames, fused_only);
  batch.run(batch_pointers, frames);
  for (std::size_t i = 0; i < models.size(); ++i) {
    INFO("creature " << i);
    const soda::State expected = reference(*models[i], jitters[i], frames);
    CHECK(compare_states(*models[i], expected, states[i]).empty());
    CHECK(compare_states(*models[i], expected, batch_states[i]).empty());
  }
  CHECK(compare_states(*models[0], states[0], states[2]).empty()); // same jitter, same run
  CHECK_FALSE(compare_states(*models[0], states[0], states[4]).empty());
  CHECK(moved);
}

TEST_CASE("the batch steppers name an invalid sine jitter with its state", "[sine_jitter]") {
  const auto scene = load_scene(models_dir() / "dainty_walker.xml");
  const soda::Model& m = scene.model;
  soda::State exact = soda::make_state(m), jittered = soda::make_state(m);
  jittered.jitter = {9, 0.002};
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // The batch steppers apply the jitter (test_lockstep_batch.cpp); an invalid one is named.
  soda::State invalid = jittered;
  invalid.jitter.probability = 1.5;
  soda::BatchStepper batch({&m, &m}, 10);
  CHECK(message([&] { batch.run({&exact, &invalid}, 10); })
            .find("BatchStepper::run: state 1: sine jitter probability must be in [0, 1], got 1.5") == 0);
  if (soda::LockstepBatch::usable()) {
    std::vector<const soda::Model*> models(8, &m);
    std::vector<soda::State> states(8, soda::make_state(m));
    states[5].jitter = {2, -0.5};
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    soda::LockstepBatch lockstep(models);
    CHECK(message([&] { lockstep.run(pointers.data(), 10); }).find("LockstepBatch::run: state 5: sine jitter probability") == 0);
    // Told which states carry jitter, BatchStepper plans the replicas in lockstep
    // before its first run; without it, the same identical Models share their sines fused.
    std::vector<bool> jitter_flags(8, true);
    jitter_flags[0] = false;
    CHECK(soda::BatchStepper(models, 10, {}, jitter_flags).lockstep_count() == 8);
    CHECK(soda::BatchStepper(models, 10).lockstep_count() == 0);
  }
  CHECK(message([&] { soda::BatchStepper({&m, &m}, 10, {}, {true}); }) == "BatchStepper: 1 jitter flags for 2 models");
}
