// The engine against the original: golden traces recorded from the 2003 Soda
// simulator (tests/data/soda/golden, copied from ../shared/models/soda/golden).
//
// With Java's sine (core/sine.hpp) every row of every trace is reproduced to the
// last bit (golden/README.md, "every row"): asserted as equality, by the reference
// step, by the fast stepper at every SIMD level and with every kernel option, and
// by `sodaevo simulate --trace` as a user runs it. The wave_wrap trace parts from
// any engine that wraps a reverse-running phase to 0.0 instead of 1.0.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <fstream>
#include <sstream>

#include "core/batch_step.hpp"
#include "core/continuous_step.hpp"
#include "core/fast_step.hpp"
#include "core/lockstep_batch.hpp"
#include "core/simd_level.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

const char* const kTraces[] = {"dw_v1_container651", "random_5",  "random_16", "random_19",
                               "random_26",          "random_49", "wave_wrap/dw_reverse_wrap"};
const char* const kCentroidRuns[] = {"dw_v1_wide100000_noautorev", "carefulslug_v2converted_wide100000",
                                     "monster_truck_v2converted_wide100000"};

/// "" when `state` equals golden row `gold` in every bit, else what differs.
std::string row_difference(const soda::Model& model, const soda::State& state, const GoldenRow& gold) {
  if (!same_bits(state.wave_phase, gold.wave_phase)) return "wave phase";
  if (static_cast<int>(state.wave_mode) != gold.wave_mode) return "wave mode";
  const std::vector<double> ours = state_values(model, state);
  if (ours.size() != gold.values.size()) return "mass count";
  for (std::size_t k = 0; k < ours.size(); ++k) {
    if (!same_bits(ours[k], gold.values[k])) {
      std::ostringstream s;
      s.precision(17);
      s << "mass " << k / 4 << " " << "xyuv"[k % 4] << ": " << ours[k] << " vs " << gold.values[k];
      return s.str();
    }
  }
  return "";
}

/// Steps a fresh state of the trace's model with `step` and compares every row;
/// returns the rows equal before the first difference and that difference.
template <class Step>
std::pair<std::size_t, std::string> rows_reproduced(const Scene& scene, const std::vector<GoldenRow>& rows,
                                                   Step&& step) {
  soda::State state = soda::make_state(scene.model);
  for (std::size_t f = 0; f < rows.size(); ++f) {
    if (f > 0) step(state);
    const std::string diff = row_difference(scene.model, state, rows[f]);
    if (!diff.empty()) return {f, "frame " + std::to_string(f) + ": " + diff};
  }
  return {rows.size(), ""};
}

} // namespace

TEST_CASE("golden traces: every row bit for bit, reference step and fast stepper", "[golden]") {
  for (const char* name : kTraces) {
    const Scene scene = load_scene(golden_dir() / (std::string(name) + ".xml"));
    const std::vector<GoldenRow> rows = read_golden_trace(golden_dir() / (std::string(name) + ".trace.txt"));
    REQUIRE(rows.size() >= 301);
    {
      const auto [equal, diff] = rows_reproduced(scene, rows, [&](soda::State& s) { soda::step(scene.model, s); });
      INFO(name << " (reference step): " << equal << " of " << rows.size() << " rows; " << diff);
      CHECK(equal == rows.size());
    }
    for (soda::SimdLevel level : supported_levels()) {
      for (int variant = 0; variant < 3; ++variant) {
        soda::FastStepOptions o;
        o.simd = level;
        o.vector_sines = variant != 1;
        o.register_frames = variant != 2;
        o.force_ordered = variant == 2;
        soda::FastStepper fast(scene.model, static_cast<long long>(rows.size()), o);
        const auto [equal, diff] = rows_reproduced(scene, rows, [&](soda::State& s) { fast.step(s); });
        INFO(name << " (fast stepper, " << soda::simd_level_name(level) << ", variant " << variant << "): " << equal
                  << " of " << rows.size() << " rows; " << diff);
        CHECK(equal == rows.size());
      }
    }
  }
}

TEST_CASE("golden traces: every row bit for bit in lockstep lanes, fused batches and the continuous mode",
          "[golden]") {
  std::vector<Scene> scenes;
  std::vector<std::vector<GoldenRow>> traces;
  for (const char* name : kTraces) {
    scenes.push_back(load_scene(golden_dir() / (std::string(name) + ".xml")));
    traces.push_back(read_golden_trace(golden_dir() / (std::string(name) + ".trace.txt")));
  }
  // Steps `states` one frame at a time with `step` and compares each with its
  // trace's row; returns the first difference ("" if none) after `frames` frames.
  auto compare_all = [&](const std::vector<int>& trace_of, std::vector<soda::State>& states, std::size_t frames,
                         const std::function<void()>& step) -> std::string {
    for (std::size_t f = 0; f <= frames; ++f) {
      if (f > 0) step();
      for (std::size_t i = 0; i < states.size(); ++i) {
        const int t = trace_of[i];
        const std::string diff = row_difference(scenes[static_cast<std::size_t>(t)].model, states[i],
                                                traces[static_cast<std::size_t>(t)][f]);
        if (!diff.empty()) return std::string(kTraces[t]) + ", state " + std::to_string(i) + ", frame " +
                                  std::to_string(f) + ": " + diff;
      }
    }
    return "";
  };
  SECTION("lockstep lanes: eight copies of each trace's model, one per lane") {
    if (!soda::LockstepBatch::usable()) {
      WARN("skipped: this machine has no lockstep lanes (AVX-512)");
      return;
    }
    for (std::size_t t = 0; t < scenes.size(); ++t) {
      if (!soda::LockstepBatch::can_take(scenes[t].model)) continue;
      std::vector<const soda::Model*> models(8, &scenes[t].model);
      soda::LockstepBatch batch(models);
      std::vector<soda::State> states(8, soda::make_state(scenes[t].model));
      std::vector<soda::State*> ptr;
      for (auto& s : states) ptr.push_back(&s);
      const std::string diff = compare_all(std::vector<int>(8, static_cast<int>(t)), states, traces[t].size() - 1,
                                           [&] { batch.run(ptr.data(), 1); });
      INFO(diff);
      CHECK(diff.empty());
    }
  }
  SECTION("fused batches: every trace's model in one BatchStepper, lockstep off and on") {
    for (bool lockstep : {false, true}) {
      std::vector<const soda::Model*> models;
      std::vector<int> trace_of;
      for (std::size_t t = 0; t < scenes.size(); ++t) {
        for (int copy = 0; copy < 2; ++copy) {
          models.push_back(&scenes[t].model);
          trace_of.push_back(static_cast<int>(t));
        }
      }
      std::vector<soda::State> states;
      for (const soda::Model* m : models) states.push_back(soda::make_state(*m));
      std::vector<soda::State*> ptr;
      for (auto& s : states) ptr.push_back(&s);
      soda::FastStepOptions o;
      o.lockstep = lockstep;
      soda::BatchStepper batch(models, 301, o);
      const std::string diff = compare_all(trace_of, states, 300, [&] { batch.run(ptr, 1); });
      INFO("lockstep " << lockstep << ": " << diff);
      CHECK(diff.empty());
    }
  }
  SECTION("the continuous mode at one Euler step per frame") {
    for (std::size_t t = 0; t < scenes.size(); ++t) {
      soda::ContinuousStepper stepper(scenes[t].model, {soda::Integrator::Euler, 1});
      std::vector<soda::State> states(1, soda::make_state(scenes[t].model));
      const std::string diff = compare_all({static_cast<int>(t)}, states, traces[t].size() - 1,
                                           [&] { stepper.step(states[0]); });
      INFO(diff);
      CHECK(diff.empty());
    }
  }
}

TEST_CASE("golden centroid runs: every 100th frame's mean bit for bit over 10,000 frames", "[golden]") {
  for (const char* name : kCentroidRuns) {
    const Scene scene = load_scene(golden_dir() / (std::string(name) + ".xml"));
    const auto rows = read_golden_centroids(golden_dir() / (std::string(name) + ".centroid.txt"));
    REQUIRE(rows.size() == 101);
    soda::State state = soda::make_state(scene.model);
    soda::FastStepper fast(scene.model, rows.back().frame);
    std::size_t equal = 0;
    for (const GoldenCentroid& row : rows) {
      fast.run(state, row.frame - state.frame);
      const soda::Point2 c = soda::mass_centroid(scene.model, state);
      const bool same = same_bits(c.x, row.mean_x) && same_bits(c.y, row.mean_y) &&
                        same_bits(state.wave_phase, row.wave_phase) &&
                        static_cast<int>(state.wave_mode) == row.wave_mode;
      if (!same) {
        FAIL_CHECK(name << ": frame " << row.frame << " differs (meanX " << c.x << " vs " << row.mean_x << ")");
        break;
      }
      ++equal;
    }
    INFO(name << ": " << equal << " of " << rows.size() << " rows");
    CHECK(equal == rows.size());
  }
}

TEST_CASE("simulate --trace, as a user runs it, reproduces every golden row", "[golden][cli]") {
  const fs::path dir = fresh_temp_dir("golden_simulate");
  for (const char* name : kTraces) {
    const std::vector<GoldenRow> rows = read_golden_trace(golden_dir() / (std::string(name) + ".trace.txt"));
    const fs::path csv = dir / "trace.csv";
    const ShellResult r = run_sodaevo("simulate " + (golden_dir() / (std::string(name) + ".xml")).string() +
                                      " --frames " + std::to_string(rows.size() - 1) + " --trace " + csv.string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line); // header
    std::size_t equal = 0;
    std::string diff;
    for (; std::getline(in, line) && equal < rows.size(); ++equal) {
      std::vector<double> cells;
      std::stringstream cs(line);
      for (std::string cell; std::getline(cs, cell, ',');) cells.push_back(std::stod(cell));
      const GoldenRow& gold = rows[equal];
      bool same = cells.size() == 3 + gold.values.size() && same_bits(cells[1], gold.wave_phase) &&
                  static_cast<int>(cells[2]) == gold.wave_mode;
      for (std::size_t k = 0; same && k < gold.values.size(); ++k) same = same_bits(cells[3 + k], gold.values[k]);
      if (!same) {
        diff = "frame " + std::to_string(equal) + " differs";
        break;
      }
    }
    INFO(name << ": " << equal << " of " << rows.size() << " rows; " << diff);
    CHECK(equal == rows.size());
  }
}
