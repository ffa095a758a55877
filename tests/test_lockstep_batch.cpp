// The lockstep batch (creatures of one shape, one per SIMD lane) against the
// reference step: every lane must equal, bit for bit, soda::run of its own model.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/batch_step.hpp"
#include "core/fast_step.hpp"
#include "core/lockstep_batch.hpp"
#include "core/step.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/algorithms/variation.hpp"
#include "core/race_lane.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

/// The lockstep kernels' levels this CPU runs (AVX2, AVX-512): each is tested.
std::vector<soda::SimdLevel> lockstep_levels() {
  std::vector<soda::SimdLevel> levels;
  for (soda::SimdLevel level : {soda::SimdLevel::Avx2, soda::SimdLevel::Avx512}) {
    if (soda::LockstepBatch::usable(level)) levels.push_back(level);
  }
  return levels;
}

/// Models of one shape as `base`, each differing from it in what a lane may
/// hold on its own: muscle phases and amplitudes, which links are muscles, rest
/// lengths, positions, the wave (speed, start phase, direction, manual), the world
/// (gravity up or off, friction, springyness, surfaces), a small box that makes
/// masses hit the walls and turn the wave, and a link of length 0.
std::vector<soda::Model> variants_of(const soda::Model& base) {
  std::vector<soda::Model> out;
  out.push_back(base);
  for (int k = 1; k <= 3; ++k) {
    soda::Model m = base;
    for (std::size_t i = 0; i < m.link_phase.size(); ++i) {
      if (m.link_muscle[i]) m.link_phase[i] = soda::wrap_phase(m.link_phase[i] + 0.0007 * k + 0.01 * static_cast<double>(i % 3));
    }
    out.push_back(m);
  }
  {
    soda::Model m = base; // springs become muscles and muscles springs; other amplitudes
    for (std::size_t i = 0; i < m.link_muscle.size(); ++i) {
      if (i % 3 == 0) {
        m.link_muscle[i] = m.link_muscle[i] ? 0 : 1;
        m.link_amplitude[i] = m.link_muscle[i] ? 0.3 : 0.0;
        m.link_phase[i] = 0.125 * static_cast<double>(i % 8);
      } else if (m.link_muscle[i]) {
        m.link_amplitude[i] *= 0.5;
      }
      m.link_rest[i] *= 1.0 + 0.01 * static_cast<double>(i % 5);
    }
    out.push_back(m);
  }
  {
    soda::Model m = base; // another wave and world
    m.wave_speed *= 1.7;
    m.wave_phase0 = soda::wrap_phase(base.wave_phase0 + 0.37);
    m.wave_direction0 = soda::WaveDirection::Reverse;
    m.gravity_direction = soda::GravityDirection::Up;
    m.friction = 0.07;
    m.springyness = std::min(0.5, base.springyness * 1.3);
    m.surface_friction = 1.0;
    m.surface_reflection = -1.0;
    out.push_back(m);
  }
  {
    soda::Model m = base; // no gravity, manual wave
    m.gravity_direction = soda::GravityDirection::Off;
    m.wave_direction0 = soda::WaveDirection::Manual;
    out.push_back(m);
  }
  {
    soda::Model m = base; // a tight box: walls, corners, autoreverse
    double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
    for (int p = 0; p < m.point_count; ++p) {
      min_x = std::min(min_x, m.x0[p]), max_x = std::max(max_x, m.x0[p]);
      min_y = std::min(min_y, m.y0[p]), max_y = std::max(max_y, m.y0[p]);
    }
    for (int p = 0; p < m.point_count; ++p) {
      m.x0[p] += 4.0 - min_x;
      m.y0[p] += 3.0 - min_y;
    }
    m.width = (max_x - min_x) + 12.0;
    m.height = (max_y - min_y) + 10.0;
    m.autoreverse = true;
    for (int p = 0; p < m.mass_count; ++p) m.vx0[p] += (p % 2 == 0 ? 3.0 : -3.0);
    out.push_back(m);
  }
  if (base.link_count() > 0 && base.is_mass(base.link_b[0])) {
    soda::Model m = base; // the first link starts at length 0 (skipped until its ends part)
    m.x0[m.link_b[0]] = m.x0[m.link_a[0]];
    m.y0[m.link_b[0]] = m.y0[m.link_a[0]];
    out.push_back(m);
  }
  {
    soda::Model m = base; // fast: the syrup limit
    for (int p = 0; p < m.mass_count; ++p) m.vx0[p] += 25.0;
    out.push_back(m);
  }
  for (soda::Model& m : out) soda::set_constants(m); // gravity, friction, muscles changed by hand
  return out;
}

/// Runs the batch and the reference side by side in uneven pieces; returns the
/// first mismatch, or an empty string.
std::string run_lockstep_and_reference(const std::string& name, const std::vector<soda::Model>& models,
                                       long long frames) {
  std::vector<const soda::Model*> pointers;
  std::vector<soda::State> lanes;
  for (const soda::Model& m : models) {
    pointers.push_back(&m);
    lanes.push_back(soda::make_state(m));
  }
  const std::vector<soda::State> start = lanes;
  for (soda::SimdLevel level : lockstep_levels()) {
    lanes = start;
    soda::LockstepBatch batch(pointers, level);
    std::vector<soda::State*> states;
    for (soda::State& s : lanes) states.push_back(&s);
    const std::string diff =
        compare_in_pieces(pointers, lanes, frames, [&](long long n) { batch.run(states.data(), n); });
    if (!diff.empty()) return name + " (" + soda::simd_level_name(level) + " kernels), " + diff;
  }
  return {};
}

bool skip_without_lockstep() {
  if (soda::LockstepBatch::usable()) return false;
  WARN("this CPU has neither AVX2 nor AVX-512: the lockstep batch is not used here (BatchStepper fuses instead)");
  return true;
}

} // namespace

TEST_CASE("lockstep batch: every bundled and test model, in variants of one shape, equals the reference",
          "[lockstep]") {
  if (skip_without_lockstep()) return;
  std::vector<fs::path> files = xml_files_under(models_dir());
  for (const fs::path& f : xml_files_under(data_dir() / "soda")) files.push_back(f);
  const fs::path shared = shared_models_dir();
  if (shared.empty()) {
    WARN("../shared is absent: the bundled and tests/data models only");
  } else {
    for (const fs::path& f : xml_files_under(shared)) files.push_back(f);
  }
  int batches = 0;
  for (const fs::path& file : files) {
    const std::optional<Scene> scene = load_scene_unless_race(file);
    if (!scene || !soda::LockstepBatch::can_take(scene->model)) continue;
    const std::vector<soda::Model> models = variants_of(scene->model);
    const std::string diff = run_lockstep_and_reference(file.string(), models, 1500);
    INFO(diff);
    CHECK(diff.empty());
    ++batches;
  }
  CHECK(batches >= 7);
}

TEST_CASE("lockstep batch: mutants of one parent (a GA's children) over a long run, 1 to 17 lanes", "[lockstep]") {
  if (skip_without_lockstep()) return;
  const Scene walker = load_scene(models_dir() / "dainty_walker.xml");
  sodaevo::RunConfig config;
  config.mutation.add_link_rate = config.mutation.remove_link_rate = 0.0; // the shape stays
  config.mutation.add_mass_rate = config.mutation.remove_mass_rate = 0.0;
  config.mutation.toggle_muscle_rate = 0.0; // the canonical form moves a toggled link to its kind's group
  std::vector<soda::Model> models;
  for (int i = 0; i < 17; ++i) {
    sodaevo::Rng rng = sodaevo::Rng::stream(99, static_cast<std::uint64_t>(i));
    soda::ModelDef child = walker.def;
    sodaevo::mutate(child, config, rng);
    models.push_back(soda::build_model(child));
    REQUIRE(soda::LockstepBatch::same_shape(models[0], models.back()));
  }
  for (std::size_t lanes : {1u, 8u, 17u}) {
    const std::vector<soda::Model> some(models.begin(), models.begin() + static_cast<std::ptrdiff_t>(lanes));
    const std::string diff = run_lockstep_and_reference("mutants", some, lanes == 17 ? 10000 : 2000);
    INFO(lanes << " lanes: " << diff);
    CHECK(diff.empty());
  }
}

TEST_CASE("lockstep batch: each lane keeps its own parameters (a one-ulp twin differs)", "[lockstep]") {
  if (skip_without_lockstep()) return;
  // The test must be able to fail: a lane that took its neighbour's springyness
  // would match the neighbour's reference, not its own.
  const soda::Model base = load_scene(models_dir() / "dainty_walker.xml").model;
  soda::Model twin = base;
  twin.springyness = std::nextafter(base.springyness, 0.0);
  soda::State a = soda::make_state(base), b = soda::make_state(twin);
  soda::run(base, a, 500);
  soda::run(twin, b, 500);
  REQUIRE_FALSE(compare_states(base, a, b).empty());
  CHECK(run_lockstep_and_reference("twins", {base, twin, base, twin, twin, base, base, twin, twin}, 1000).empty());
}

TEST_CASE("lockstep batch: shapes", "[lockstep]") {
  const soda::Model walker = load_scene(models_dir() / "dainty_walker.xml").model;
  const soda::Model slug = load_scene(models_dir() / "carefulslug.xml").model;
  soda::Model swapped = walker; // one link's ends the other way round: another shape
  std::swap(swapped.link_a[0], swapped.link_b[0]);
  soda::Model other_numbers = walker;
  other_numbers.link_rest[0] *= 2.0;
  other_numbers.link_muscle[1] = other_numbers.link_muscle[1] ? 0 : 1;
  CHECK(soda::LockstepBatch::same_shape(walker, other_numbers));
  CHECK_FALSE(soda::LockstepBatch::same_shape(walker, swapped));
  CHECK_FALSE(soda::LockstepBatch::same_shape(walker, slug));
  if (!soda::LockstepBatch::usable()) return;
  CHECK_THROWS_AS(soda::LockstepBatch({&walker, &slug}), std::invalid_argument);
  CHECK_THROWS_AS(soda::LockstepBatch({}), std::invalid_argument);
  int barred = 0;
  for (const fs::path& file : xml_files_under(data_dir() / "soda")) {
    const std::optional<Scene> scene = load_scene_unless_race(file);
    if (!scene || scene->model.bar_count() == 0) continue;
    const soda::Model& model = scene->model;
    CHECK(soda::LockstepBatch::can_take(model)); // fixed bars between fixed nodes
    soda::Model moved_bar = model; // one bar a little elsewhere: other bars, another shape
    moved_bar.fixed_bars.bars[0].x1 = std::nextafter(model.fixed_bars.bars[0].x1, 1e300);
    CHECK_FALSE(soda::LockstepBatch::same_shape(model, moved_bar));
    CHECK_THROWS_AS(soda::LockstepBatch({&model, &moved_bar}), std::invalid_argument);
    soda::Model other_rule = model; // the other original's box test
    other_rule.fixed_bars.engine = model.fixed_bars.engine == soda::BarEngine::Racer2004
                                       ? soda::BarEngine::SodaConstructor2003
                                       : soda::BarEngine::Racer2004;
    CHECK_FALSE(soda::LockstepBatch::same_shape(model, other_rule));
    if (model.mass_count > 0) {
      soda::Model mass_end = model; // a bar with a mass at an end (BarKind::MovingEnds): not taken
      mass_end.bar_a[0] = 0;
      CHECK_FALSE(soda::LockstepBatch::can_take(mass_end));
      CHECK_THROWS_AS(soda::LockstepBatch({&mass_end}), std::invalid_argument);
    }
    ++barred;
  }
  CHECK(barred > 0);
}

TEST_CASE("BatchStepper: how many of a shape go in lockstep", "[lockstep]") {
  CHECK(soda::lockstep_share(5) == 0);
  CHECK(soda::lockstep_share(6) == 6);
  CHECK(soda::lockstep_share(8) == 8);
  CHECK(soda::lockstep_share(13) == 8); // 5 left over: fused
  CHECK(soda::lockstep_share(14) == 14);
}

TEST_CASE("BatchStepper: six or more models of one shape go in lockstep, the rest fused, all exact", "[lockstep]") {
  const soda::Model walker = load_scene(models_dir() / "dainty_walker.xml").model;
  const soda::Model slug = load_scene(models_dir() / "carefulslug.xml").model;
  const soda::Model wheel = load_scene(models_dir() / "wheel.xml").model;
  const soda::Model truck = load_scene(models_dir() / "monster_truck.xml").model;
  std::vector<soda::Model> walkers = variants_of(walker);
  for (std::size_t k = 0; k < walkers.size(); ++k) { // each its own muscle phases: no sine shared
    for (std::size_t i = 0; i < walkers[k].link_phase.size(); ++i) {
      walkers[k].link_phase[i] = soda::wrap_phase(walkers[k].link_phase[i] + 0.01 * static_cast<double>(k));
    }
  }
  std::vector<const soda::Model*> models = {&slug};
  for (std::size_t k = 0; k < 6; ++k) models.push_back(&walkers[k]);
  models.push_back(&wheel);
  models.push_back(&slug);
  for (int k = 0; k < 4; ++k) models.push_back(&wheel); // five wheels in all: fused
  for (int k = 0; k < 8; ++k) models.push_back(&truck); // eight identical trucks share every sine: fused
  std::vector<soda::State> ref, fast;
  for (const soda::Model* m : models) {
    ref.push_back(soda::make_state(*m));
    fast.push_back(soda::make_state(*m));
  }
  soda::BatchStepper batch(models, 3000);
  CHECK(batch.lockstep_count() == (soda::LockstepBatch::usable() ? 6 : 0));
  CHECK(soda::shared_sine_fraction(models, {0}) == 0.0);
  CHECK(soda::shared_sine_fraction(models, {1, 2, 3, 4, 5, 6}) == 0.0);
  CHECK(soda::shared_sine_fraction(models, {13, 14, 15, 16, 17, 18, 19, 20}) == Approx(7.0 / 8.0));
  CHECK(batch.fused_count() == static_cast<int>(models.size()));
  std::vector<soda::State*> states;
  for (soda::State& s : fast) states.push_back(&s);
  batch.run(states, 1000);
  batch.run(states, 2000);
  for (std::size_t k = 0; k < models.size(); ++k) {
    soda::run(*models[k], ref[k], 3000);
    INFO("entry " << k);
    CHECK(compare_states(*models[k], ref[k], fast[k]).empty());
  }
}

namespace {

/// K replicas of `model` (one Model, K states) with distinct jitter seeds
/// 1..K-1 and replica 0 exact, stepped by `step` against soda::run with the same
/// jitter; the first mismatch, or an empty string. `moved` is set when some
/// jittered replica ends away from the exact one (the jitter took effect).
std::string replicas_against_reference(const soda::Model& model, int replicas, double probability, long long frames,
                                       const std::function<void(const std::vector<const soda::Model*>&,
                                                                std::vector<soda::State*>&, long long)>& step,
                                       bool& moved) {
  const std::vector<const soda::Model*> models(static_cast<std::size_t>(replicas), &model);
  std::vector<soda::State> states;
  for (int r = 0; r < replicas; ++r) {
    states.push_back(soda::make_state(model));
    states.back().jitter = {static_cast<std::uint64_t>(r), probability};
  }
  std::vector<soda::State*> pointers;
  for (soda::State& s : states) pointers.push_back(&s);
  const std::string diff = compare_in_pieces(models, states, frames, [&](long long n) { step(models, pointers, n); });
  for (int r = 1; r < replicas; ++r) moved = moved || !compare_states(model, states[0], states[r]).empty();
  return diff;
}

} // namespace

TEST_CASE("jittered replicas of each bundled model: lockstep lanes and BatchStepper equal the reference step",
          "[lockstep][sine_jitter]") {
  bool moved = false;
  const Scene walker = load_scene(models_dir() / "dainty_walker.xml");
  const soda::Model& other = walker.model;
  for (const fs::path& file : xml_files_under(models_dir())) {
    const std::optional<Scene> scene = sodaevo::test::load_scene_unless_race(file);
    if (!scene) continue; // a race file (models/terrains) holds no model
    const soda::Model& model = scene->model;
    for (int replicas : {8, 6, 3}) {
      for (double probability : {0.002, 0.05}) {
        INFO(file.filename().string() << ", " << replicas << " replicas, p = " << probability);
        const long long frames = 2000;
        if (soda::LockstepBatch::can_take(model) && soda::LockstepBatch::usable()) {
          soda::LockstepBatch batch(std::vector<const soda::Model*>(static_cast<std::size_t>(replicas), &model));
          CHECK(replicas_against_reference(
                    model, replicas, probability, frames,
                    [&](const auto&, std::vector<soda::State*>& s, long long n) { batch.run(s.data(), n); }, moved)
                    .empty());
        }
        // BatchStepper with another creature's exact state among the replicas.
        std::unique_ptr<soda::BatchStepper> batch;
        soda::State other_state = soda::make_state(other), other_ref = other_state;
        CHECK(replicas_against_reference(
                  model, replicas, probability, frames,
                  [&](const std::vector<const soda::Model*>& m, std::vector<soda::State*>& s, long long n) {
                    std::vector<const soda::Model*> all = m;
                    all.push_back(&other);
                    std::vector<soda::State*> all_states = s;
                    all_states.push_back(&other_state);
                    if (!batch) batch = std::make_unique<soda::BatchStepper>(all, frames);
                    batch->run(all_states, n);
                  },
                  moved)
                  .empty());
        soda::run(other, other_ref, frames);
        CHECK(compare_states(other, other_ref, other_state).empty());
        if (soda::LockstepBatch::usable() && soda::LockstepBatch::can_take(model) && replicas >= soda::kMinLockstep) {
          CHECK(batch->lockstep_count() == replicas); // the replicas went in lockstep
        }
      }
    }
  }
  CHECK(moved); // the jitter changed some trajectory: the comparisons above could fail
}

namespace {

/// A lane of a batch of several shapes: its model and its sine jitter.
struct LockstepLane {
  const soda::Model* model;
  std::uint64_t seed;
  double probability;
};

/// `k` replicas of `model` (replica r with seed first_seed + r, seed 0 exact).
std::vector<LockstepLane> replicas_of(const soda::Model& model, int k, std::uint64_t first_seed, double probability) {
  std::vector<LockstepLane> lanes;
  for (int r = 0; r < k; ++r) lanes.push_back({&model, first_seed + static_cast<std::uint64_t>(r), probability});
  return lanes;
}

/// The states of `shapes`' lanes, flattened, with their jitter.
std::vector<soda::State> states_of(const std::vector<std::vector<LockstepLane>>& shapes) {
  std::vector<soda::State> states;
  for (const std::vector<LockstepLane>& lanes : shapes) {
    for (const LockstepLane& l : lanes) {
      states.push_back(soda::make_state(*l.model));
      states.back().jitter = {l.seed, l.probability};
    }
  }
  return states;
}

} // namespace

TEST_CASE("lockstep batch of several shapes: replicas sharing their sines, mixed shapes, partial groups, a batch "
          "reused, every lane equals the reference",
          "[lockstep][sine_jitter]") {
  if (skip_without_lockstep()) return;
  const soda::Model walker = load_scene(models_dir() / "dainty_walker.xml").model;
  const soda::Model slug = load_scene(models_dir() / "carefulslug.xml").model;
  const std::vector<soda::Model> variants = variants_of(walker);
  const soda::Model& boxed = variants[7]; // a tight box with autoreverse: the replicas' waves turn apart
  REQUIRE(boxed.autoreverse);
  std::vector<LockstepLane> mixed; // walker's shape, 9 different models: 8 + 1 lanes, no sine shared
  for (std::size_t k = 0; k < 9; ++k) mixed.push_back({&variants[k % variants.size()], k % 2, 0.05});
  const std::vector<std::vector<LockstepLane>> shapes = {
      replicas_of(walker, 8, 0, 0.01),  // one creature's replicas: sines shared, jittered lanes
      mixed,                            // the same links: stepped side by side with the group before
      replicas_of(slug, 3, 5, 0.01),    // another shape, a partial group
      replicas_of(boxed, 8, 0, 0.05),   // waves that part: the shared sines fall back to each lane's
      replicas_of(walker, 6, 0, 0.0),   // exact lanes only: sines shared, no jitter
  };
  std::vector<std::vector<const soda::Model*>> models;
  std::vector<const soda::Model*> flat;
  for (const std::vector<LockstepLane>& lanes : shapes) {
    models.emplace_back();
    for (const LockstepLane& l : lanes) {
      models.back().push_back(l.model);
      flat.push_back(l.model);
    }
  }
  for (soda::SimdLevel level : lockstep_levels()) { // each level the CPU runs
    INFO(soda::simd_level_name(level) << " kernels");
    soda::LockstepBatch batch = soda::LockstepBatch::of_shapes(models, level);
    REQUIRE(batch.size() == 34);
    REQUIRE(batch.group_count() == 6);
    CHECK(batch.shares_sines(0));
    CHECK_FALSE(batch.shares_sines(1));
    CHECK(batch.shares_sines(3));
    CHECK(batch.shares_sines(4));
    CHECK(batch.shares_sines(5));
    std::vector<soda::State> states = states_of(shapes);
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    const std::string diff = compare_in_pieces(flat, states, 3000, [&](long long n) { batch.run(pointers.data(), n); });
    INFO(diff);
    CHECK(diff.empty());
    // The test could fail: jittered replicas left their exact replica 0, and the
    // boxed replicas' waves parted (their sines were no longer shared).
    CHECK_FALSE(compare_states(walker, states[0], states[1]).empty());
    bool waves_parted = false;
    for (int r = 1; r < 8; ++r) waves_parted = waves_parted || states[20].wave_phase != states[20 + static_cast<std::size_t>(r)].wave_phase;
    CHECK(waves_parted);
    // The same batch on other states: other seeds, from another start.
    std::vector<std::vector<LockstepLane>> again = shapes;
    for (std::vector<LockstepLane>& lanes : again) {
      for (LockstepLane& l : lanes) l.seed = l.seed == 0 ? 0 : l.seed + 100;
    }
    std::vector<soda::State> other = states_of(again);
    for (soda::State& s : other) s.x[0] += 1.5;
    pointers.clear();
    for (soda::State& s : other) pointers.push_back(&s);
    const std::string diff_again = compare_in_pieces(flat, other, 1000, [&](long long n) { batch.run(pointers.data(), n); });
    INFO(diff_again);
    CHECK(diff_again.empty());
  }
  CHECK_THROWS_AS(soda::LockstepBatch::of_shapes({}), std::invalid_argument);
  CHECK_THROWS_AS(soda::LockstepBatch::of_shapes({{&walker}, {}}), std::invalid_argument);
  CHECK_THROWS_AS(soda::LockstepBatch::of_shapes({{&walker, &slug}}), std::invalid_argument);
}

TEST_CASE("BatchStepper: the GA's batch of replicas (creatures of several shapes x 8) in one lockstep batch, "
          "exact, and again on other states",
          "[lockstep][sine_jitter]") {
  const soda::Model walker = load_scene(models_dir() / "dainty_walker.xml").model;
  const soda::Model slug = load_scene(models_dir() / "carefulslug.xml").model;
  const soda::Model wheel = load_scene(models_dir() / "wheel.xml").model;
  const std::vector<soda::Model> variants = variants_of(walker);
  // As the replica estimator orders its rollouts: each creature's replicas in a
  // row, replica 0 exact; one creature scored once, exact.
  std::vector<std::vector<LockstepLane>> runs = {replicas_of(walker, 8, 0, 0.01), replicas_of(slug, 8, 0, 0.01),
                                         replicas_of(variants[7], 8, 0, 0.05), {{&wheel, 0, 0.0}},
                                         replicas_of(variants[2], 8, 0, 0.01)};
  std::vector<const soda::Model*> models;
  std::vector<bool> jittered;
  for (const std::vector<LockstepLane>& lanes : runs) {
    for (const LockstepLane& l : lanes) {
      models.push_back(l.model);
      jittered.push_back(l.seed != 0);
    }
  }
  soda::BatchStepper stepper(models, 3000, {}, jittered);
  if (soda::LockstepBatch::usable()) CHECK(stepper.lockstep_count() == 32);
  for (int round = 0; round < 2; ++round) {
    std::vector<std::vector<LockstepLane>> these = runs;
    for (std::vector<LockstepLane>& lanes : these) {
      for (LockstepLane& l : lanes) l.seed = l.seed == 0 ? 0 : l.seed + 50 * static_cast<std::uint64_t>(round);
    }
    std::vector<soda::State> states = states_of(these);
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    const std::string diff = compare_in_pieces(models, states, 2000, [&](long long n) { stepper.run(pointers, n); });
    INFO("round " << round << ": " << diff);
    CHECK(diff.empty());
  }
}

namespace {
/// The Dainty Walker placed in the TerrainFlat lane, as the racer places it.
soda::Model dainty_in_flat_lane() {
  const soda::RaceDef race = soda::read_race_file(models_dir() / "terrains" / "TerrainFlat.xml");
  const soda::RaceLane lane = soda::build_lane(
      race.terrain, race.constraints, soda::read_model_file(models_dir() / "dainty_walker.xml").def, "dainty_walker");
  return soda::build_lane_model(lane);
}
} // namespace

// Issue 27: race replicas (K states of one lane Model with fixed bars) in lockstep.
// The reference runs the bar rules for every moving mass in its step; the lanes run
// them after the mass pass (bar_pass), each against its own State's BarMemory, which
// compare_states compares too.
TEST_CASE("lockstep batch: jittered replicas of a racer in a TerrainFlat lane equal the reference, bar memory "
          "included; BatchStepper puts them in lockstep",
          "[lockstep][race]") {
  if (skip_without_lockstep()) return;
  const soda::Model model = dainty_in_flat_lane();
  REQUIRE(model.bar_count() > 0);
  REQUIRE(soda::LockstepBatch::can_take(model));
  constexpr long long kFrames = 700; // falls onto the platform, walks on it
  constexpr int kReplicas = 11;      // a full group and a partial one (padding lanes)
  bool moved = false;
  for (soda::SimdLevel level : lockstep_levels()) {
    INFO(soda::simd_level_name(level) << " kernels");
    soda::LockstepBatch batch(std::vector<const soda::Model*>(kReplicas, &model), level);
    CHECK(replicas_against_reference(
              model, kReplicas, 0.02, kFrames,
              [&](const auto&, std::vector<soda::State*>& s, long long n) { batch.run(s.data(), n); }, moved)
              .empty());
    CHECK(moved); // the replicas parted: a lane that took another's bar memory would differ
    // The bars acted: every replica's masses lie on a bar (its memory is compared above).
    CHECK(batch.bar_rules_run() > kReplicas * kFrames);
  }
  soda::State landed = soda::make_state(model);
  soda::run(model, landed, kFrames);
  CHECK_FALSE(landed.bar_memory.contacts.empty());

  std::unique_ptr<soda::BatchStepper> stepper;
  CHECK(replicas_against_reference(
            model, kReplicas, 0.02, kFrames,
            [&](const std::vector<const soda::Model*>& m, std::vector<soda::State*>& s, long long n) {
              if (!stepper) stepper = std::make_unique<soda::BatchStepper>(m, kFrames);
              stepper->run(s, n);
            },
            moved)
            .empty());
  CHECK(stepper->lockstep_count() == soda::lockstep_share(kReplicas)); // 8 in lockstep, 3 fused
  CHECK(soda::lockstep_share(kReplicas) == 8);
}

// A race's finish: each replica stops at its own frame, as FastStepper::run_until
// stops it (the same final state, bar memory included, and the same frame count).
TEST_CASE("lockstep batch run_until: race replicas stop each at its own frame, as FastStepper::run_until",
          "[lockstep][race]") {
  if (skip_without_lockstep()) return;
  const soda::Model model = dainty_in_flat_lane();
  constexpr int kReplicas = 10;
  constexpr long long kFrames = 1500;
  const soda::State start = soda::make_state(model);
  double start_lo = start.x[0];
  for (int p = 1; p < model.mass_count; ++p) start_lo = std::min(start_lo, start.x[static_cast<std::size_t>(p)]);
  // Replica c's finish line (the walker walks left, ~0.4 px a frame): further for
  // later replicas; the last never finishes.
  const auto stop_of = [&](int c) {
    return [&, c](double lo, double) { return c < kReplicas - 1 && lo < start_lo - 100.0 - 40.0 * c; };
  };
  std::vector<soda::State> by_one(kReplicas, start), in_lanes(kReplicas, start);
  for (int c = 0; c < kReplicas; ++c) by_one[c].jitter = in_lanes[c].jitter = {static_cast<std::uint64_t>(c), 0.02};
  std::vector<long long> expected(kReplicas);
  for (int c = 0; c < kReplicas; ++c) {
    soda::FastStepper stepper(model, kFrames);
    expected[c] = stepper.run_until(by_one[c], kFrames, stop_of(c));
  }
  soda::LockstepBatch batch(std::vector<const soda::Model*>(kReplicas, &model));
  std::vector<soda::State*> pointers;
  for (soda::State& s : in_lanes) pointers.push_back(&s);
  std::vector<long long> done;
  const long long ran = batch.run_until(pointers.data(), kFrames, [&](int c, double lo, double hi) { return stop_of(c)(lo, hi); }, done);
  CHECK(ran == kFrames);
  CHECK(done == expected);
  for (int c = 0; c < kReplicas; ++c) {
    INFO("replica " << c << ", stopped after " << expected[c]);
    CHECK(compare_states(model, by_one[c], in_lanes[c]).empty());
    CHECK(in_lanes[c].frame == by_one[c].frame);
  }
  // The test could fail: the replicas stopped at different frames, before the end.
  CHECK(*std::min_element(expected.begin(), expected.end() - 1) < *std::max_element(expected.begin(), expected.end() - 1));
  CHECK(expected.back() == kFrames);
  CHECK(expected.front() < kFrames);
}

TEST_CASE("SIMD level: forced below the CPU's best, Auto follows it, lockstep included", "[lockstep][simd]") {
  const soda::SimdLevel best = soda::best_simd_level();
  soda::SimdLevel parsed = soda::SimdLevel::Auto;
  CHECK(soda::parse_simd_level("avx2", parsed));
  CHECK(parsed == soda::SimdLevel::Avx2);
  CHECK_FALSE(soda::parse_simd_level("avx3", parsed));
  soda::force_simd_level(soda::SimdLevel::Sse2);
  CHECK(soda::best_simd_level() == soda::SimdLevel::Sse2);
  CHECK_FALSE(soda::LockstepBatch::usable()); // no SSE2 lockstep kernels: BatchStepper fuses
  if (soda::simd_level_supported(soda::SimdLevel::Avx2)) {
    soda::force_simd_level(soda::SimdLevel::Avx2);
    CHECK(soda::best_simd_level() == soda::SimdLevel::Avx2);
    CHECK(soda::LockstepBatch::level_for(soda::SimdLevel::Auto) == soda::SimdLevel::Avx2);
    const soda::Model walker = load_scene(models_dir() / "dainty_walker.xml").model;
    CHECK(soda::LockstepBatch(std::vector<const soda::Model*>(8, &walker)).level() == soda::SimdLevel::Avx2);
  }
  // Auto is the CPU's best (whatever SODAEVO_SIMD said at start-up); then the level
  // in force before this test is put back, so a run under SODAEVO_SIMD keeps it.
  soda::force_simd_level(soda::SimdLevel::Auto);
  const soda::SimdLevel cpu_best = soda::simd_level_supported(soda::SimdLevel::Avx512) ? soda::SimdLevel::Avx512
                                   : soda::simd_level_supported(soda::SimdLevel::Avx2) ? soda::SimdLevel::Avx2
                                                                                      : soda::SimdLevel::Sse2;
  CHECK(soda::best_simd_level() == cpu_best);
  soda::force_simd_level(best);
  CHECK(soda::best_simd_level() == best);
}
