// Fixed bars to the last bit: the 240 scenes of tests/data/terrain/lastbit (copied
// from ../shared/models/soda/golden/terrain/lastbit; GOLDEN_README.md there), each
// traced by the original it names (2003 simulator or 2004 racer). No muscles, so no
// sine: every row must equal the trace in every bit, in every stepper - the
// reference step, simulate's default stepper, the fast stepper at each SIMD level,
// all scenes in one fused scene, and (AVX-512) the lockstep lanes. The rules these
// scenes pin down are docs/physics.md's "The last bits" (core/fixed_bars.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/fast_step.hpp"
#include "core/fixed_bars.hpp"
#include "core/fused/fused_scene.hpp"
#include "core/lockstep_batch.hpp"
#include "core/simd_level.hpp"
#include "core/step.hpp"
#include "core/stepping.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

fs::path lastbit_dir() { return data_dir() / "terrain" / "lastbit"; }

struct LastbitScene {
  std::string name, suite;
  soda::Model model;
  std::vector<GoldenRow> rows; ///< frames 0..N
};

/// Every scene of scenes.tsv, built with the bar engine that traced it.
const std::vector<LastbitScene>& lastbit_scenes() {
  static const std::vector<LastbitScene> scenes = [] {
    std::vector<LastbitScene> out;
    std::ifstream tsv(lastbit_dir() / "scenes.tsv");
    std::string line;
    std::getline(tsv, line); // header: scene suite bar_engine frames
    while (std::getline(tsv, line)) {
      std::istringstream fields(line);
      std::string name, suite, engine_text;
      long long frames = 0;
      fields >> name >> suite >> engine_text >> frames;
      soda::BarEngine engine{};
      REQUIRE(soda::parse_bar_engine(engine_text, engine));
      LastbitScene s;
      s.name = name;
      s.suite = suite;
      s.model = soda::build_model(soda::read_model_file(lastbit_dir() / (name + ".xml")).def, engine);
      s.rows = read_golden_trace(lastbit_dir() / (name + ".trace.txt"));
      REQUIRE(static_cast<long long>(s.rows.size()) == frames + 1);
      out.push_back(std::move(s));
    }
    return out;
  }();
  return scenes;
}

std::string lastbit_full_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

/// Empty if `state` equals golden row `f` of `scene` in every bit, else where not.
std::string row_difference(const LastbitScene& scene, const soda::State& state, std::size_t f) {
  const GoldenRow& gold = scene.rows[f];
  const std::vector<double> ours = state_values(scene.model, state);
  const std::string at = scene.name + " frame " + std::to_string(f) + ": ";
  if (ours.size() != gold.values.size()) return at + "mass count";
  if (!same_bits(state.wave_phase, gold.wave_phase) || static_cast<int>(state.wave_mode) != gold.wave_mode) {
    return at + "wave";
  }
  const char* const names[] = {"x", "y", "vx", "vy"};
  for (std::size_t k = 0; k < ours.size(); ++k) {
    if (!same_bits(ours[k], gold.values[k])) {
      return at + "mass " + std::to_string(k / 4) + " " + names[k % 4] + " ours " + lastbit_full_text(ours[k]) + ", golden " +
             lastbit_full_text(gold.values[k]);
    }
  }
  return {};
}

/// One frame of one scene's state.
using StepOne = std::function<void(soda::State&)>;

/// Steps each scene alone, frame by frame, with the stepper `make(scene)` gives,
/// and returns the first difference of each scene that has one.
std::vector<std::string> run_each(const std::function<StepOne(const LastbitScene&)>& make) {
  std::vector<std::string> failures;
  for (const LastbitScene& scene : lastbit_scenes()) {
    soda::State state = soda::make_state(scene.model);
    const StepOne step_one = make(scene);
    std::string diff = row_difference(scene, state, 0);
    for (std::size_t f = 1; f < scene.rows.size() && diff.empty(); ++f) {
      step_one(state);
      diff = row_difference(scene, state, f);
    }
    if (!diff.empty()) failures.push_back(diff);
  }
  return failures;
}

/// One failed check per failing scene (its first difference), then the count.
void check_all_exact(const std::vector<std::string>& failures) {
  for (const std::string& f : failures) {
    INFO(f);
    CHECK(false);
  }
  INFO("scenes with a difference: " << failures.size());
  CHECK(failures.empty());
}

} // namespace

TEST_CASE("terrain last bit: the golden set is whole (240 scenes, each suite and engine)", "[terrain][lastbit]") {
  std::map<std::string, int> per_suite;
  for (const LastbitScene& s : lastbit_scenes()) {
    ++per_suite[s.suite + " " + soda::bar_engine_name(s.model.fixed_bars.engine)];
    CHECK(s.model.bar_count() > 0);
  }
  CHECK(lastbit_scenes().size() == 240);
  CHECK(per_suite == std::map<std::string, int>{{"ends 2003", 40}, {"invbox 2004", 40}, {"lowfar 2003", 40},
                                                {"lowfar 2004", 40}, {"wall 2003", 40}, {"wall 2004", 40}});
}

TEST_CASE("terrain last bit: the reference step gives every row of the 240 traces bit for bit", "[terrain][lastbit]") {
  check_all_exact(run_each([](const LastbitScene& scene) {
    return StepOne([&scene](soda::State& s) { soda::step(scene.model, s); });
  }));
}

// simulate's default: FrameStepper in soda mode, i.e. the fast stepper (SIMD level auto).
TEST_CASE("terrain last bit: simulate's stepper gives every row bit for bit", "[terrain][lastbit]") {
  std::vector<std::unique_ptr<soda::FrameStepper>> keep;
  check_all_exact(run_each([&keep](const LastbitScene& scene) {
    keep.push_back(std::make_unique<soda::FrameStepper>(scene.model, soda::Stepping{},
                                                        static_cast<long long>(scene.rows.size())));
    soda::FrameStepper* stepper = keep.back().get();
    return StepOne([stepper](soda::State& s) { stepper->step(s); });
  }));
}

TEST_CASE("terrain last bit: the fast stepper at every SIMD level, and its ordered kernel, bit for bit",
          "[terrain][lastbit]") {
  for (const soda::SimdLevel level : supported_levels()) {
    for (const bool ordered : {false, true}) {
      INFO("SIMD level " << static_cast<int>(level) << (ordered ? ", ordered kernel" : ""));
      soda::FastStepOptions options;
      options.simd = level;
      options.force_ordered = ordered;
      std::vector<std::unique_ptr<soda::FastStepper>> keep;
      check_all_exact(run_each([&](const LastbitScene& scene) {
        keep.push_back(
            std::make_unique<soda::FastStepper>(scene.model, static_cast<long long>(scene.rows.size()), options));
        soda::FastStepper* stepper = keep.back().get();
        return StepOne([stepper](soda::State& s) { stepper->step(s); });
      }));
    }
  }
}

namespace {

/// Steps states together, one frame per call of `step_all`; states[j] is a state
/// of scene scene_of[j], compared with its rows as long as it has them. Returns
/// the first difference of each state that has one.
std::vector<std::string> run_together(const std::vector<std::size_t>& scene_of,
                                      const std::function<void(std::vector<soda::State*>&)>& step_all) {
  const std::vector<LastbitScene>& scenes = lastbit_scenes();
  std::vector<soda::State> states;
  for (std::size_t k : scene_of) states.push_back(soda::make_state(scenes[k].model));
  std::vector<soda::State*> pointers;
  for (soda::State& s : states) pointers.push_back(&s);
  std::size_t longest = 0;
  for (const LastbitScene& s : scenes) longest = std::max(longest, s.rows.size());
  std::vector<std::string> first(states.size());
  for (std::size_t f = 0; f < longest; ++f) {
    if (f > 0) step_all(pointers);
    for (std::size_t j = 0; j < states.size(); ++j) {
      const LastbitScene& scene = scenes[scene_of[j]];
      if (f < scene.rows.size() && first[j].empty()) first[j] = row_difference(scene, states[j], f);
    }
  }
  std::vector<std::string> failures;
  for (const std::string& d : first) {
    if (!d.empty()) failures.push_back(d);
  }
  return failures;
}

} // namespace

TEST_CASE("terrain last bit: all 240 scenes in one fused scene, at every SIMD level, bit for bit",
          "[terrain][lastbit][fused_bars]") {
  std::vector<const soda::Model*> models;
  std::vector<std::size_t> scene_of;
  for (const LastbitScene& s : lastbit_scenes()) {
    scene_of.push_back(models.size());
    models.push_back(&s.model);
  }
  for (const soda::SimdLevel level : supported_levels()) {
    INFO("SIMD level " << static_cast<int>(level));
    soda::FastStepOptions options;
    options.simd = level;
    soda::FusedScene scene(models, 100, options);
    check_all_exact(run_together(scene_of, [&](std::vector<soda::State*>& p) { scene.run(p.data(), 1); }));
  }
}

TEST_CASE("terrain last bit: lockstep lanes (AVX-512), each scene its own shape, bit for bit",
          "[terrain][lastbit][lockstep]") {
  if (!soda::LockstepBatch::usable()) {
    WARN("this CPU has no AVX-512: no lockstep lanes here");
    return;
  }
  // Each scene twice (a lane group of two); the lanes do not take a bar with a
  // mass at an end.
  std::vector<std::vector<const soda::Model*>> shapes;
  std::vector<std::size_t> scene_of;
  const std::vector<LastbitScene>& scenes = lastbit_scenes();
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    if (!soda::LockstepBatch::can_take(scenes[k].model)) continue;
    shapes.push_back({&scenes[k].model, &scenes[k].model});
    scene_of.insert(scene_of.end(), {k, k});
  }
  INFO("scenes in lanes: " << shapes.size());
  CHECK(shapes.size() >= 200);
  soda::LockstepBatch batch = soda::LockstepBatch::of_shapes(shapes);
  check_all_exact(run_together(scene_of, [&](std::vector<soda::State*>& p) { batch.run(p.data(), 1); }));
}
