// Fixed bars against the originals: the 22 golden micro-scenes of
// tests/data/terrain/scenes (copied from ../shared/models/soda/golden/terrain; README
// there), traced from the 2003 SodaConstructor engine and, where it differs, from the
// 2004 racer's copy. Expected: every row bit for bit (the README: "a re-implementation
// that follows terrain-research.md reproduces all of them bit for bit"), the three
// walker_hills scenes included, whose muscles take Java's sine (core/sine.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/fast_step.hpp"
#include "core/fixed_bars.hpp"
#include "formats/model_file.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

std::string full(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

fs::path scenes_dir() { return data_dir() / "terrain" / "scenes"; }

struct SceneRun {
  long long rows = 0;
  long long bit_exact_rows = 0; ///< leading rows equal in every bit
  long long first_difference = -1;
  std::string where;           ///< the first differing value
  double max_error = 0.0;      ///< positions and velocities, over all rows
};

SceneRun run_scene(const std::string& name, soda::BarEngine engine, bool fast = false) {
  const fs::path xml = scenes_dir() / (name + ".xml");
  fs::path trace = scenes_dir() / (name + ".trace.txt");
  if (engine == soda::BarEngine::Racer2004 && fs::exists(scenes_dir() / (name + ".trace2004.txt"))) {
    trace = scenes_dir() / (name + ".trace2004.txt");
  }
  const soda::ModelDef def = soda::read_model_file(xml).def;
  const soda::Model model = soda::build_model(def, engine);
  const std::vector<GoldenRow> rows = read_golden_trace(trace);
  REQUIRE(rows.size() > 1);
  soda::State state = soda::make_state(model);
  soda::FastStepper stepper(model, static_cast<long long>(rows.size()));
  SceneRun r;
  r.rows = static_cast<long long>(rows.size());
  for (std::size_t f = 0; f < rows.size(); ++f) {
    if (f > 0) {
      if (fast) {
        stepper.step(state);
      } else {
        soda::step(model, state);
      }
    }
    const std::vector<double> ours = state_values(model, state);
    const GoldenRow& gold = rows[f];
    REQUIRE(ours.size() == gold.values.size());
    bool exact = same_bits(state.wave_phase, gold.wave_phase) && static_cast<int>(state.wave_mode) == gold.wave_mode;
    for (std::size_t k = 0; k < ours.size(); ++k) {
      r.max_error = std::max(r.max_error, std::fabs(ours[k] - gold.values[k]));
      if (exact && !same_bits(ours[k], gold.values[k])) {
        exact = false;
        if (r.first_difference < 0) {
          const char* const names[] = {"x", "y", "vx", "vy"};
          r.where = "mass " + std::to_string(k / 4) + " " + names[k % 4] + ": ours " + full(ours[k]) + ", golden " + full(gold.values[k]);
        }
      }
    }
    if (!exact && r.first_difference < 0) r.first_difference = static_cast<long long>(f);
    if (r.first_difference < 0) ++r.bit_exact_rows;
  }
  return r;
}

const char* const kExactScenes[] = {
    "cross_sloped_sticky", "cross_from_below", "rest_on_bar",      "start_on_bar",      "land_exactly",
    "slide_along_line",    "slide_sloped_slippery", "bar_ends",    "slide_off_end",     "colinear_join",
    "concave_v_stuck",     "concave_v_reversed", "concave_step_exit", "convex_hilltop", "two_bars_one_move",
    "floor_and_bar",       "wall_and_bar",     "bar_between_masses", "mass_on_own_bar"};

const char* const kWalkerScenes[] = {"walker_hills_430", "walker_hills_121", "walker_hills_7"};

} // namespace

TEST_CASE("terrain golden micro-scenes: every row bit for bit, 2003 and 2004 engines", "[terrain][golden]") {
  std::vector<const char*> scenes(std::begin(kExactScenes), std::end(kExactScenes));
  scenes.insert(scenes.end(), std::begin(kWalkerScenes), std::end(kWalkerScenes)); // muscles: Java's sine
  for (const char* name : scenes) {
    for (soda::BarEngine engine : {soda::BarEngine::SodaConstructor2003, soda::BarEngine::Racer2004}) {
      for (bool fast : {false, true}) {
        const SceneRun r = run_scene(name, engine, fast);
        INFO(name << " engine " << soda::bar_engine_name(engine) << (fast ? " FastStepper" : " reference")
                  << ": bit-exact rows " << r.bit_exact_rows << " of " << r.rows << ", first difference at frame "
                  << r.first_difference << " (" << r.where << "), max error " << r.max_error);
        CHECK(r.bit_exact_rows == r.rows);
      }
    }
  }
}

// The rule matters: where the README marks a scene as differing between the
// originals, the other engine's rule does not reproduce the trace.
TEST_CASE("terrain golden micro-scenes: the 2004 rule does not give the 2003 trace where they differ",
          "[terrain][golden]") {
  int differing = 0;
  for (const char* name : kExactScenes) {
    if (!fs::exists(scenes_dir() / (std::string(name) + ".trace2004.txt"))) continue;
    ++differing;
    const fs::path xml = scenes_dir() / (std::string(name) + ".xml");
    const soda::Model model = soda::build_model(soda::read_model_file(xml).def, soda::BarEngine::Racer2004);
    const std::vector<GoldenRow> rows = read_golden_trace(scenes_dir() / (std::string(name) + ".trace.txt"));
    soda::State state = soda::make_state(model);
    bool all_equal = true;
    for (std::size_t f = 1; f < rows.size() && all_equal; ++f) {
      soda::step(model, state);
      const std::vector<double> ours = state_values(model, state);
      for (std::size_t k = 0; k < ours.size(); ++k) all_equal = all_equal && same_bits(ours[k], rows[f].values[k]);
    }
    INFO(name);
    CHECK_FALSE(all_equal);
  }
  CHECK(differing == 7); // scenes/index.tsv: 10 differ, 3 of them the walkers
}

// The fast steppers leave out the bar rules for a mass that no bar remembers, no
// corner holds and whose move move_may_touch_bars passes over (fused/ordered.cpp,
// bar_pass). That is exact only if the rules would then change nothing: checked here
// against collide_with_fixed_bars itself for moves that end exactly on bar ends,
// joints and corners of the golden micro-scenes, and on tile edges where a bar
// starts or ends exactly on the edge (a tile that left such a bar out goes red).
TEST_CASE("fixed bars: a move the bar pre-test passes over changes nothing in the bar rules", "[terrain]") {
  std::vector<soda::Model> models;
  for (const char* name : kExactScenes) {
    const soda::ModelDef def = soda::read_model_file(scenes_dir() / (std::string(name) + ".xml")).def;
    for (soda::BarEngine engine : {soda::BarEngine::SodaConstructor2003, soda::BarEngine::Racer2004}) {
      models.push_back(soda::build_model(def, engine));
    }
  }
  // Bars on tile edges: the grid starts at the least x (0), tiles are 128 px wide.
  const std::vector<double> px = {0, 100, 128, 300, 256, 384, 512, 400}, py = {10, 10, 10, 10, 40, 20, 20, 300};
  for (soda::BarEngine engine : {soda::BarEngine::SodaConstructor2003, soda::BarEngine::Racer2004}) {
    soda::Model m;
    m.fixed_bars = soda::make_fixed_bars({0, 2, 4, 6}, {1, 3, 5, 7}, px.data(), py.data(), engine);
    REQUIRE(m.fixed_bars.cell_width == 128.0);
    models.push_back(m);
  }
  long long skipped = 0, touched = 0;
  for (const soda::Model& model : models) {
    const soda::FixedBars& bars = model.fixed_bars;
    if (bars.empty()) continue;
    std::vector<std::pair<double, double>> targets; // ends, joints, corners, tile edges
    for (const soda::FixedBar& b : bars.bars) {
      targets.insert(targets.end(), {{b.x1, b.y1}, {b.x2, b.y2}, {b.x1 + b.w, b.y1 + b.h}, {(b.x1 + b.x2) / 2, (b.y1 + b.y2) / 2}});
    }
    for (int c = 0; c < bars.cell_count; ++c) {
      const double edge = bars.cell_tile[soda::FixedBars::kTileStride * static_cast<std::size_t>(c) + 1];
      if (std::isfinite(edge)) {
        for (const soda::FixedBar& b : bars.bars) targets.push_back({edge, b.y1});
      }
    }
    const double offsets[] = {-7.0, -1.0, -1e-4, 0.0, 1e-4, 2.5};
    for (const auto& [tx, ty] : targets) {
      for (double sx : offsets) {
        for (double sy : offsets) {
          for (double ex : {0.0, 1e-4, -1e-4}) {
            const double x0 = tx + sx, y0 = ty + sy, x = tx + ex, y = ty;
            soda::BarMemory memory;
            memory.corners.resize(1);
            const soda::BarMemory before = memory;
            const soda::MassMove move{x0, y0, x, y, x, y, x - x0, y - y0};
            const soda::Surface surface{0.1, -0.75, 1e6, 1e6};
            soda::MassEnd end;
            const bool hit = soda::collide_with_fixed_bars(bars, memory, 0, move, surface, end);
            const bool changed = hit || !(memory == before);
            if (!soda::move_may_touch_bars(bars, x0, y0, x, y)) {
              ++skipped;
              INFO("move (" << full(x0) << ", " << full(y0) << ") -> (" << full(x) << ", " << full(y) << ")");
              CHECK_FALSE(changed);
            } else if (changed) {
              ++touched;
            }
          }
        }
      }
    }
  }
  CHECK(skipped > 1000);
  CHECK(touched > 1000);
}

// Golden lane inc1_3_elite_i281 (tests/data/terrain/lanes), frame 5993 -> 5994, mass 5
// alone: it lies on the node (50179, 6) where bar 0 ends and bar 1 begins (a concave
// joint), 1 ulp above both lines; bar 0 remembers it on side 0. Its move crosses both
// lines, and both crossing points round to the node, at the same distance from its
// start. The move and velocity are the engine's after links, gravity and friction
// (the lane test holds every other value of the frame to the trace); the expected
// numbers are the trace's row 5994. Bar 0 with its joint would put the mass 9.25 px
// along bar 1 (the end point projected on it, velocity bar 0's); the original answers
// with bar 1, crossed first along the move: a slide of Fs = 0.1 of the move along it.
TEST_CASE("fixed bars at a shared end point: the bar crossed first along the move answers (lane inc1_3_elite_i281, "
          "frame 5994)",
          "[terrain][golden]") {
  const std::vector<double> px = {50000.0, 50179.0, 50407.0}, py = {-1.0, 6.0, 34.0};
  const soda::MassMove move{50179.0,           6.000000000000001,   50188.825747131275, 2.447368186937058,
                            50188.825747131275, 2.447368186937058, 9.8257471312728253, -3.5526318130629431};
  REQUIRE(move.x == move.x0 + move.vx);
  REQUIRE(move.y == move.y0 + move.vy);
  const soda::Surface surface{0.1, -0.75, 100653.0, 422.0}; // the lane's
  // Either link order: the answer is the geometry's, not the order's.
  for (const bool bar_0_first : {true, false}) {
    const std::vector<int> a = bar_0_first ? std::vector<int>{0, 1} : std::vector<int>{1, 0};
    const std::vector<int> b = bar_0_first ? std::vector<int>{1, 2} : std::vector<int>{2, 1};
    const soda::FixedBars bars = soda::make_fixed_bars(a, b, px.data(), py.data(), soda::BarEngine::Racer2004);
    soda::BarMemory memory;
    memory.corners.resize(1);
    memory.remember(bar_0_first ? 0 : 1, 0, 0);
    soda::MassEnd end;
    INFO("bar 0 first in link order: " << bar_0_first);
    REQUIRE(soda::collide_with_fixed_bars(bars, memory, 0, move, surface, end));
    INFO("ours " << full(end.x) << " " << full(end.y) << " " << full(end.vx) << " " << full(end.vy));
    CHECK(same_bits(end.x, 50179.924995522626)); // the trace's row 5994, as written there
    CHECK(same_bits(end.y, 6.1135959413747365));
    CHECK(same_bits(end.vx, 0.49315159383746754));
    CHECK(same_bits(end.vy, 3.6300393614822000));
  }
}
