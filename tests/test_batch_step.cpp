// The batch stepper against the reference step: K models fused on one thread must
// give, for each model, exactly what soda::run gives for that model alone.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/batch_step.hpp"
#include "core/continuous_step.hpp"
#include "core/fast_step.hpp"
#include "core/fused/fused_scene.hpp"
#include "core/input_error.hpp"
#include "core/lockstep_batch.hpp"
#include "core/step.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

/// The models of every file under `dir` that the engine takes (race files are skipped).
void add_directory(const fs::path& dir, std::vector<std::pair<std::string, soda::Model>>& out) {
  if (dir.empty() || !fs::is_directory(dir)) return;
  for (const fs::path& file : xml_files_under(dir)) {
    if (std::optional<Scene> scene = load_scene_unless_race(file)) out.emplace_back(file.string(), std::move(scene->model));
  }
}

/// Random creatures as the GA makes and scores them (Sodarace scaling gives each
/// its own gravity), some with their own friction, springyness and surfaces, some
/// put in a small box with autoreverse on so that they hit walls.
void add_random_creatures(int count, std::uint64_t seed, std::vector<std::pair<std::string, soda::Model>>& out) {
  sodaevo::RunConfig config;
  config.world.evolve = {"friction", "springyness", "surface_friction", "surface_reflection"};
  config.fitness.frames = 3000;
  config.fitness.settle_frames = 100;
  for (int i = 0, made = 0; made < count && i < 50 * count; ++i) {
    sodaevo::Rng rng = sodaevo::Rng::stream(seed, static_cast<std::uint64_t>(i));
    soda::ModelDef c = sodaevo::random_creature(config, rng);
    c.environment.friction = 0.01 * (i % 7);
    c.environment.springyness = 0.1 + 0.05 * (i % 5);
    c.collisions.surface_friction = 0.1 * (i % 4);
    c.collisions.surface_reflection = -0.2 * (i % 5);
    soda::ModelDef prepared;
    try {
      prepared = sodaevo::walk_problem_of(config).prepare(c);
    } catch (const soda::InputError&) {
      continue; // scaled gravity above the original's limit
    }
    if (i % 3 == 1) {
      // A tight box: walls, corners and autoreverse.
      double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
      for (const soda::NodeDef& n : prepared.nodes) {
        min_x = std::min(min_x, n.x), max_x = std::max(max_x, n.x);
        min_y = std::min(min_y, n.y), max_y = std::max(max_y, n.y);
      }
      for (soda::NodeDef& n : prepared.nodes) {
        n.x += 10.0 - min_x;
        n.y += 5.0 - min_y;
      }
      prepared.width = static_cast<int>(max_x - min_x) + 60;
      prepared.height = static_cast<int>(max_y - min_y) + 40;
      prepared.settings.autoreverse = true;
      if (i % 2 == 0) prepared.settings.gravity_direction = soda::GravityDirection::Up;
    }
    out.emplace_back("random creature " + std::to_string(i), soda::build_model(prepared));
    ++made;
  }
}

/// Runs the batch and the reference side by side in uneven pieces; returns the
/// first mismatch, or an empty string.
std::string run_batch_and_reference(const std::vector<std::pair<std::string, soda::Model>>& models,
                                    const std::vector<int>& picks, long long frames, soda::FastStepOptions options,
                                    int* fused_count = nullptr, int* scene_count = nullptr) {
  std::vector<const soda::Model*> batch_models;
  std::vector<soda::State> fast;
  for (int p : picks) {
    batch_models.push_back(&models[p].second);
    fast.push_back(soda::make_state(models[p].second));
  }
  soda::BatchStepper batch(batch_models, frames, options);
  if (fused_count) *fused_count = batch.fused_count();
  if (scene_count) *scene_count = batch.scene_count();
  std::vector<soda::State*> states;
  for (soda::State& s : fast) states.push_back(&s);
  const std::string diff = compare_in_pieces(batch_models, fast, frames, [&](long long n) { batch.run(states, n); });
  if (diff.empty()) return diff;
  const std::size_t k = std::stoul(diff.substr(diff.find(' ') + 1)); // "entry k at ..."
  return models[picks[k]].first + " (batch " + diff + ")";
}

std::vector<int> all_indices(std::size_t n) {
  std::vector<int> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<int>(i);
  return v;
}

} // namespace

TEST_CASE("batch of every model, random creatures and duplicates equals separate reference runs", "[batch_step]") {
  std::vector<std::pair<std::string, soda::Model>> models;
  add_directory(data_dir() / "soda", models);
  add_directory(shared_models_dir(), models);
  add_directory(models_dir(), models);
  const std::size_t files = models.size();
  add_random_creatures(24, 11, models);
  REQUIRE(files > 10);
  REQUIRE(models.size() >= files + 20);
  // Every model once, then duplicates of a few (each entry has its own state).
  std::vector<int> picks = all_indices(models.size());
  for (int d : {0, 1, static_cast<int>(files), static_cast<int>(files) + 1, static_cast<int>(models.size()) - 1}) {
    picks.push_back(d);
  }
  for (soda::SimdLevel level : supported_levels()) {
    soda::FastStepOptions opt;
    opt.simd = level;
    int fused = 0, scenes = 0;
    const std::string diff = run_batch_and_reference(models, picks, 3000, opt, &fused, &scenes);
    INFO(soda::simd_level_name(level) << ": " << diff);
    CHECK(diff.empty());
    CHECK(fused > static_cast<int>(picks.size()) / 2); // most models are fused
    CHECK(scenes > 1);                                 // packed into several scenes of <= kMaxFusedLinks
    CHECK(scenes < fused / 2);                         // most scenes hold several models
  }
}

TEST_CASE("batches of size 1 and of odd sizes equal the reference", "[batch_step]") {
  std::vector<std::pair<std::string, soda::Model>> models;
  add_random_creatures(12, 23, models);
  add_directory(models_dir(), models);
  REQUIRE(models.size() >= 12);
  for (std::size_t size : {1u, 3u, 5u, 7u, 9u}) {
    std::vector<int> picks;
    for (std::size_t k = 0; k < size; ++k) picks.push_back(static_cast<int>((k * 5 + size) % models.size()));
    const std::string diff = run_batch_and_reference(models, picks, 5000, {});
    INFO("size " << size << ": " << diff);
    CHECK(diff.empty());
  }
}

TEST_CASE("batch: table sines off and fixed walls give the same bits", "[batch_step]") {
  std::vector<std::pair<std::string, soda::Model>> models;
  add_random_creatures(8, 5, models);
  soda::FastStepOptions opt;
  opt.vector_sines = false;
  opt.adaptive_walls = false;
  CHECK(run_batch_and_reference(models, all_indices(models.size()), 2000, opt).empty());
}

TEST_CASE("batch: models with fixed bars are fused, in scenes of their own", "[batch_step]") {
  std::vector<std::pair<std::string, soda::Model>> models;
  add_directory(data_dir() / "soda", models);
  add_random_creatures(4, 3, models);
  std::vector<int> picks;
  int with_bars = 0;
  for (std::size_t i = 0; i < models.size(); ++i) {
    if (models[i].second.bar_count() > 0 && with_bars < 3) {
      picks.push_back(static_cast<int>(i));
      ++with_bars;
    }
  }
  if (with_bars == 0) {
    WARN("no model with fixed bars in tests/data/soda");
    return;
  }
  for (std::size_t i = models.size() - 4; i < models.size(); ++i) picks.push_back(static_cast<int>(i));
  int fused = 0, scenes = 0;
  CHECK(run_batch_and_reference(models, picks, 2000, {}, &fused, &scenes).empty());
  CHECK(fused == static_cast<int>(picks.size()));
  CHECK(scenes == 2);
}

TEST_CASE("batch: the comparison sees a difference of one creature's parameter", "[batch_step]") {
  // The test must be able to fail: a creature whose springyness differs by one
  // ulp from its twin's gives different bits, so sharing the twin's parameters
  // would be caught.
  std::vector<std::pair<std::string, soda::Model>> models;
  add_random_creatures(2, 17, models);
  soda::Model twin = models[0].second;
  twin.springyness = std::nextafter(twin.springyness, 0.0);
  soda::State a = soda::make_state(models[0].second), b = soda::make_state(twin);
  soda::run(models[0].second, a, 500);
  soda::run(twin, b, 500);
  CHECK_FALSE(compare_states(twin, a, b).empty());
  models.emplace_back("twin", twin);
  CHECK(run_batch_and_reference(models, {0, 2, 1, 2, 0}, 1000, {}).empty());
}

TEST_CASE("batch: creatures sharing wave and muscle phases share sines and stay exact", "[batch_step]") {
  // A GA population shares most genes: the fused scene computes each distinct
  // (wave state, muscle phase) sine once per frame. Copies that share everything,
  // some, or nothing, and copies whose waves part (autoreverse in a small box,
  // another speed or start phase, a manual wave) must all stay exact.
  const soda::Model base = load_scene(models_dir() / "dainty_walker.xml").model;
  std::vector<std::pair<std::string, soda::Model>> models;
  for (int k = 0; k < 4; ++k) models.emplace_back("copy", base);
  soda::Model shifted = base; // every muscle phase its own
  for (std::size_t i = 0; i < shifted.link_phase.size(); ++i) {
    if (shifted.link_muscle[i]) shifted.link_phase[i] = soda::wrap_phase(shifted.link_phase[i] + 0.001 * (i + 1));
  }
  models.emplace_back("shifted phases", shifted);
  soda::Model one_changed = base; // one muscle phase changed: the others still shared
  for (std::size_t i = 0; i < one_changed.link_phase.size(); ++i) {
    if (one_changed.link_muscle[i]) {
      one_changed.link_phase[i] = soda::wrap_phase(one_changed.link_phase[i] + 0.25);
      break;
    }
  }
  models.emplace_back("one phase changed", one_changed);
  soda::Model faster = base;
  faster.wave_speed *= 1.5;
  models.emplace_back("faster wave", faster);
  soda::Model later = base;
  later.wave_phase0 = soda::wrap_phase(base.wave_phase0 + 0.5);
  models.emplace_back("later wave", later);
  soda::Model boxed = base; // hits the side walls: its wave turns, the copies' do not
  double max_x = 0;
  for (int p = 0; p < boxed.mass_count; ++p) max_x = std::max(max_x, boxed.x0[p]);
  boxed.width = max_x + 30.0;
  boxed.autoreverse = true;
  models.emplace_back("boxed, autoreverse", boxed);
  soda::Model manual = base;
  manual.wave_direction0 = soda::WaveDirection::Manual;
  models.emplace_back("manual wave", manual);
  const std::vector<int> picks = all_indices(models.size());
  // Also a batch whose waves are in one state but whose arguments all differ.
  const std::vector<int> same_wave_no_shared_phase = {0, 4};
  for (soda::SimdLevel level : supported_levels()) {
    soda::FastStepOptions opt;
    opt.simd = level;
    for (const std::vector<int>* p : {&picks, &same_wave_no_shared_phase}) {
      const std::string diff = run_batch_and_reference(models, *p, 4000, opt);
      INFO(soda::simd_level_name(level) << ", " << p->size() << " creatures: " << diff);
      CHECK(diff.empty());
    }
  }
  // Identical copies evaluate the sines of one creature.
  soda::FastStepper alone(base, 1000);
  soda::State s = soda::make_state(base);
  alone.run(s, 1000);
  soda::FusedScene copies({&base, &base, &base, &base}, 1000);
  std::vector<soda::State> states(4, soda::make_state(base));
  soda::State* const ptrs[4] = {&states[0], &states[1], &states[2], &states[3]};
  copies.run(ptrs, 1000);
  CHECK(copies.sines_evaluated() == alone.sines_evaluated());
  for (const soda::State& c : states) CHECK(compare_states(base, s, c).empty());
}

TEST_CASE("batch: standing waves shared between creatures stay exact", "[batch_step]") {
  // Every wave manual: fill_rows computes one row of sines for all. With more than
  // 16 groups, some shared between creatures, the targets read the distinct sines
  // directly (core/fused/sine_rows.cpp), not a copy by group.
  soda::Model base = load_scene(models_dir() / "dainty_walker.xml").model;
  base.wave_direction0 = soda::WaveDirection::Manual;
  soda::Model shifted = base;
  for (std::size_t i = 0; i < shifted.link_phase.size(); ++i) {
    if (shifted.link_muscle[i]) shifted.link_phase[i] = soda::wrap_phase(shifted.link_phase[i] + 0.001 * (i + 1));
  }
  std::vector<std::pair<std::string, soda::Model>> models;
  for (int k = 0; k < 3; ++k) models.emplace_back("manual copy", base);
  for (int k = 0; k < 3; ++k) models.emplace_back("manual, shifted phases", shifted);
  for (soda::SimdLevel level : supported_levels()) {
    soda::FastStepOptions opt;
    opt.simd = level;
    const std::string diff = run_batch_and_reference(models, all_indices(models.size()), 3000, opt);
    INFO(soda::simd_level_name(level) << ": " << diff);
    CHECK(diff.empty());
  }
}

// Every stepper's run() checks the states it is given before its frames: the frame
// loops index them by the model's points without bounds checks, and one State
// given for two creatures would be stepped twice per frame. Each case fails if
// the check is missing: a wrong size is then read out of bounds (AddressSanitizer
// in CI, or no exception), a State given twice runs without an error.
TEST_CASE("steppers refuse a state of another model, a null state and one State given twice", "[batch_step]") {
  const Scene walker = load_scene(models_dir() / "dainty_walker.xml");
  const Scene slug = load_scene(models_dir() / "carefulslug.xml");
  const soda::Model& m = walker.model;
  REQUIRE(m.point_count != slug.model.point_count);
  const auto refuses = [](auto&& call, const std::string& says) {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(says) != std::string::npos);
      return true;
    }
    return false;
  };
  const std::string size_message = "expected " + std::to_string(m.point_count) + " points in x, y, vx and vy, got " +
                                   std::to_string(slug.model.point_count);
  soda::State other = soda::make_state(slug.model);
  CHECK(refuses([&] { soda::run(m, other, 10); }, "soda::run: the state does not fit the model: " + size_message));
  CHECK(refuses([&] { soda::step(m, other); }, "soda::step: "));
  soda::FastStepper fast(m, 100);
  CHECK(refuses([&] { fast.run(other, 10); }, "FastStepper::run: states[0]: the state does not fit"));
  CHECK(refuses([&] { fast.step(other); }, "FastStepper::run: "));
  soda::ContinuousSettings settings;
  soda::ContinuousStepper continuous(m, settings);
  CHECK(refuses([&] { continuous.run(other, 10); }, "ContinuousStepper::run: the state does not fit the model: " + size_message));

  // Batches: a State twice (checked pairwise up to 32 states, sorted above), null,
  // of another model.
  for (int count : {2, 7, 40}) {
    INFO("batch of " << count);
    std::vector<const soda::Model*> models(static_cast<std::size_t>(count), &m);
    std::vector<soda::State> states(static_cast<std::size_t>(count), soda::make_state(m));
    std::vector<soda::State*> ptrs;
    for (soda::State& s : states) ptrs.push_back(&s);
    soda::BatchStepper batch(models, 100);
    const std::vector<soda::State*> good = ptrs;
    ptrs.back() = ptrs.front();
    CHECK(refuses([&] { batch.run(ptrs, 10); },
                  "BatchStepper::run: states[" + std::to_string(count - 1) + "] is the same State as states[0]"));
    ptrs.back() = nullptr;
    CHECK(refuses([&] { batch.run(ptrs, 10); }, "states[" + std::to_string(count - 1) + "] is null"));
    ptrs.back() = &other;
    CHECK(refuses([&] { batch.run(ptrs, 10); }, "states[" + std::to_string(count - 1) + "]: the state does not fit"));
    // The refused calls changed nothing; the good batch still runs.
    CHECK_NOTHROW(batch.run(good, 10));
    CHECK(states.front().frame == 10);
    if (soda::LockstepBatch::usable()) {
      soda::LockstepBatch lockstep(models);
      ptrs = good;
      ptrs[1] = ptrs[0];
      CHECK(refuses([&] { lockstep.run(ptrs.data(), 10); }, "LockstepBatch::run: states[1] is the same State"));
    }
  }
}
