// Sodarace lanes and races against the original racer (2004, easysoda.jar): the 8
// golden lanes of tests/data/terrain/lanes (the racer's lane model at frame 0 and its
// per-frame trace) and a subset of the 880 golden race results (races.tsv); all 880
// run in `sodaevo bench races`. Golden data copied from
// ../shared/models/soda/golden/terrain (README there).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "bench/golden_races.hpp"
#include "core/input_error.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "core/batch_step.hpp"
#include "core/lockstep_batch.hpp"
#include "core/race_lane.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

fs::path terrain_dir() { return data_dir() / "terrain"; }

/// A path of the golden data ("shared/models/soda/...") in tests/data.
fs::path golden_path(const std::string& p) {
  const std::string terrain = "shared/models/soda/golden/terrain/";
  const std::string soda = "shared/models/soda/";
  if (p.rfind(terrain, 0) == 0) return terrain_dir() / p.substr(terrain.size());
  if (p.rfind(soda, 0) == 0) return data_dir() / "soda" / p.substr(soda.size());
  return p;
}

struct LaneCase {
  std::string name, race, contender;
};

std::vector<LaneCase> lane_cases() {
  std::ifstream in(terrain_dir() / "lanes_list.txt");
  std::vector<LaneCase> out;
  LaneCase c;
  int frames = 0;
  while (in >> c.name >> c.race >> c.contender >> frames) out.push_back(c);
  return out;
}

soda::RaceLane lane_for(const std::string& race, const std::string& contender) {
  const soda::RaceDef r = soda::read_race_file(golden_path(race));
  const soda::ModelDef c = soda::read_model_file(golden_path(contender)).def;
  return soda::build_lane(r.terrain, r.constraints, c, contender);
}

} // namespace

TEST_CASE("race lanes at frame 0 equal the racer's, bit for bit", "[race][golden]") {
  const auto cases = lane_cases();
  REQUIRE(cases.size() == 8);
  for (const LaneCase& k : cases) {
    INFO(k.name);
    const soda::RaceLane lane = lane_for(k.race, k.contender);
    const soda::ModelDef gold = soda::read_model_file(terrain_dir() / "lanes" / (k.name + ".lane.xml")).def;
    CHECK(lane.def.width == gold.width);
    CHECK(lane.def.height == gold.height);
    CHECK(same_bits(lane.def.environment.gravity, gold.environment.gravity));
    CHECK(lane.def.environment == gold.environment);
    CHECK(lane.def.collisions == gold.collisions);
    CHECK(lane.def.wave == gold.wave);
    CHECK(lane.def.settings == gold.settings);
    REQUIRE(lane.def.nodes.size() == gold.nodes.size());
    for (std::size_t i = 0; i < gold.nodes.size(); ++i) {
      INFO("node " << i);
      CHECK(lane.def.nodes[i].fixed == gold.nodes[i].fixed);
      CHECK(same_bits(lane.def.nodes[i].x, gold.nodes[i].x));
      CHECK(same_bits(lane.def.nodes[i].y, gold.nodes[i].y));
      CHECK(same_bits(lane.def.nodes[i].vx, gold.nodes[i].vx));
      CHECK(same_bits(lane.def.nodes[i].vy, gold.nodes[i].vy));
    }
    // Links: the golden file groups them (bars first); each group in the same order.
    std::vector<soda::LinkDef> ours_bars, ours_links, gold_bars, gold_links;
    for (const auto& l : lane.def.links) (l.kind == soda::LinkKind::FixedBar ? ours_bars : ours_links).push_back(l);
    for (const auto& l : gold.links) (l.kind == soda::LinkKind::FixedBar ? gold_bars : gold_links).push_back(l);
    CHECK(ours_bars == gold_bars);
    REQUIRE(ours_links.size() == gold_links.size());
    for (std::size_t i = 0; i < gold_links.size(); ++i) {
      INFO("link " << i);
      CHECK(ours_links[i].a == gold_links[i].a);
      CHECK(ours_links[i].b == gold_links[i].b);
      CHECK(same_bits(ours_links[i].rest_length, gold_links[i].rest_length));
    }
  }
}

namespace {

/// A lane's golden trace: lanes/NAME.trace.txt, or NAME.trace.txt.gz for a long one.
/// Each row starts with its frame, which must be the row's index.
std::vector<GoldenRow> lane_trace(const std::string& name) {
  fs::path path = terrain_dir() / "lanes" / (name + ".trace.txt");
  if (!fs::exists(path)) path += ".gz";
  std::vector<GoldenRow> rows;
  for (const std::string& line : read_lines(path)) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    long long frame = -1;
    GoldenRow row;
    fields >> frame >> row.wave_phase >> row.wave_mode;
    REQUIRE(frame == static_cast<long long>(rows.size()));
    for (double v = 0.0; fields >> v;) row.values.push_back(v);
    rows.push_back(std::move(row));
  }
  return rows;
}

struct LaneRun {
  long long rows = 0, bit_exact_rows = 0; ///< rows equal in every state, from frame 0 on
  double max_error = 0.0;
  std::string first_difference; ///< "frame F, value V (mass V/4): golden G, ours O"
};

/// Follows `trace` with `states` (states of `model`, at frame 0), `step` advancing
/// each by one frame before every row after the first.
LaneRun follow_trace(const soda::Model& model, const std::vector<GoldenRow>& trace, std::vector<soda::State>& states,
                     const std::function<void()>& step) {
  LaneRun r;
  bool exact_so_far = true;
  for (const GoldenRow& row : trace) {
    if (r.rows > 0) step();
    for (const soda::State& state : states) {
      bool exact = same_bits(row.wave_phase, state.wave_phase) && row.wave_mode == static_cast<int>(state.wave_mode);
      const std::vector<double> ours = state_values(model, state);
      REQUIRE(ours.size() == row.values.size());
      for (std::size_t v = 0; v < ours.size(); ++v) {
        r.max_error = std::max(r.max_error, std::fabs(ours[v] - row.values[v]));
        if (same_bits(ours[v], row.values[v])) continue;
        if (exact && exact_so_far) {
          std::ostringstream d;
          d.precision(17);
          d << "frame " << r.rows << ", value " << v << " (mass " << v / 4 << "): golden " << row.values[v] << ", ours "
            << ours[v];
          r.first_difference = d.str();
        }
        exact = false;
      }
      exact_so_far = exact_so_far && exact;
    }
    r.bit_exact_rows += exact_so_far ? 1 : 0;
    ++r.rows;
  }
  return r;
}

/// The lane of case `k` as the racer builds it.
soda::Model lane_model(const LaneCase& k) { return soda::build_lane_model(lane_for(k.race, k.contender)); }

LaneRun run_lane_trace(const LaneCase& k) {
  const soda::Model model = lane_model(k);
  std::vector<soda::State> states{soda::make_state(model)};
  return follow_trace(model, lane_trace(k.name), states, [&] { soda::step(model, states[0]); });
}

/// The rows of each golden lane's trace (frames 0..N).
const std::map<std::string, long long>& lane_rows() {
  static const std::map<std::string, long long> rows = {
      {"flat_m2", 325},           {"hilly_dw_wavereverse", 301}, {"hilly_walker_560", 301},
      {"race05_walker_430", 301}, {"inc1_2_walker_353", 301},    {"ai_walker_121", 301},
      {"race10_walker_202", 301}, {"inc1_3_elite_i281", 10004}};
  return rows;
}

} // namespace

// The README of the golden lanes: a port following the rules of docs/physics.md's "Fixed bars" matched
// race05_walker_430 and ai_walker_121 only up to frames 33 and 36 (floor-and-bar
// collisions), the other five bit for bit over the whole trace; with the last-bit rules
// of docs/physics.md's "The last bits" (tests/test_terrain_lastbit.cpp) all seven match
// over their whole traces. inc1_3_elite_i281 (a whole race, 10,004 rows) parted at frame
// 5994 while the nearest rounded crossing point chose between two bars at a shared end
// point; the crossing first along the move is the original's choice.
TEST_CASE("race lanes frame by frame: bit for bit over every row", "[race][golden]") {
  for (const LaneCase& k : lane_cases()) {
    const LaneRun r = run_lane_trace(k);
    INFO(k.name << ": bit-exact rows " << r.bit_exact_rows << " of " << r.rows << ", max error " << r.max_error
                << ", first difference " << r.first_difference);
    REQUIRE(lane_rows().count(k.name) == 1);
    CHECK(r.rows == lane_rows().at(k.name));
    CHECK(r.bit_exact_rows == r.rows);
  }
}

// The same traces through every other stepper: the fast one at every SIMD level this
// CPU runs (and its per-mass ordered kernel), fused scenes (BatchStepper) and lockstep
// lanes (LockstepBatch, where the CPU has AVX-512). All reach the bar rules through
// rules::complete_move, but each picks the masses that take them on its own.
TEST_CASE("race lanes frame by frame: every stepper and SIMD level, bit for bit over every row", "[race][golden]") {
  for (const LaneCase& k : lane_cases()) {
    const soda::Model model = lane_model(k);
    const std::vector<GoldenRow> trace = lane_trace(k.name);
    const long long frames = static_cast<long long>(trace.size()) - 1;
    const auto check = [&](const std::string& stepper, std::vector<soda::State>& states,
                           const std::function<void()>& step) {
      const LaneRun r = follow_trace(model, trace, states, step);
      INFO(k.name << ", " << stepper << ": bit-exact rows " << r.bit_exact_rows << " of " << r.rows
                  << ", first difference " << r.first_difference);
      CHECK(r.bit_exact_rows == lane_rows().at(k.name));
    };
    for (const soda::SimdLevel level : supported_levels()) {
      for (const bool ordered : {false, true}) {
        soda::FastStepOptions options;
        options.simd = level;
        options.force_ordered = ordered;
        soda::FastStepper fast(model, frames, options);
        std::vector<soda::State> states{soda::make_state(model)};
        check(std::string("fast ") + soda::simd_level_name(level) + (ordered ? " ordered" : ""), states,
              [&] { fast.step(states[0]); });
      }
    }
    soda::FastStepOptions fused_only;
    fused_only.lockstep = false;
    const std::vector<const soda::Model*> three(3, &model);
    soda::BatchStepper fused(three, frames, fused_only);
    std::vector<soda::State> fused_states(3, soda::make_state(model));
    std::vector<soda::State*> fused_pointers{&fused_states[0], &fused_states[1], &fused_states[2]};
    REQUIRE(fused.fused_count() == 3);
    check("fused", fused_states, [&] { fused.run(fused_pointers, 1); });
    if (soda::LockstepBatch::usable()) {
      const std::vector<const soda::Model*> lanes(soda::LockstepBatch::kLanes, &model);
      soda::LockstepBatch lockstep(lanes);
      std::vector<soda::State> lock_states(lanes.size(), soda::make_state(model));
      std::vector<soda::State*> lock_pointers;
      for (soda::State& s : lock_states) lock_pointers.push_back(&s);
      check("lockstep", lock_states, [&] { lockstep.run(lock_pointers.data(), 1); });
    }
  }
}

// The original racer's result for the lane above, inc1_3_elite_i281 (a held-out race
// of an evolved contender; golden README, "lanes/inc1_3_elite_i281"): a timeout.
TEST_CASE("race result of elite_i281 on inc1_3: the original racer's 10001.82421875", "[race][golden]") {
  const soda::RaceDef race = soda::read_race_file(data_dir() / "soda/wwagner4_wodka/lib_wodka_jar/terrain/inc1_3.xml");
  const std::string contender = "elite_i281.xml";
  const soda::RaceLane lane = soda::build_lane(
      race.terrain, race.constraints, soda::read_model_file(terrain_dir() / "contenders" / contender).def, contender);
  const soda::Model model = soda::build_lane_model(lane);
  CHECK(soda::run_race(lane, model, race.timeout).result == 10001.82421875);
  soda::State state = soda::make_state(model);
  CHECK(soda::run_race_fast(lane, model, race.timeout, state).result == 10001.82421875);
}

// The original racer's results (races.tsv), to the last bit of the result: all 880
// (`sodaevo bench races` explains any difference); the three races the inferred bar
// rules come from are also tested alone in test_races_inferred.cpp.
TEST_CASE("golden race results: all 880 of the original racer's, to the last bit", "[race][golden]") {
  // tests/data/terrain/races.tsv: 20 race files x 44 contenders, results of the 2004
  // racer. Every one must be reproduced: the muscles take Java's sine, the lanes the
  // contender filter and the bar rules of docs/physics.md.
  const auto races = sodaevo::bench::race_golden(data_dir());
  REQUIRE(races.size() == 880);
  int same = 0;
  for (const auto& g : races) {
    if (g.same()) {
      ++same;
    } else {
      UNSCOPED_INFO(g.race << " " << g.contender << ": original " << g.golden << ", ours " << g.ours);
    }
  }
  CHECK(same == 880);
}

TEST_CASE("race results: a timeout is timeout + fraction, the finish is two frames before the update",
          "[race]") {
  soda::RaceLane lane;
  lane.start_x = 50000.0;
  lane.finish_x = 50651.0;
  soda::RaceOutcome o;
  // Spec 3.2: finish when (int)min x > finish.x + 6, result U - 2.
  CHECK_FALSE(soda::race_ends(lane, 10000, 500, 50657.9, 50700.0, o)); // (int) 50657 is not > 50657
  REQUIRE(soda::race_ends(lane, 10000, 500, 50658.0, 50700.0, o));
  CHECK(o.finished);
  CHECK(o.result == 498.0);
  // Timeout at update T + 3: T + (finish + 6 - left) / (finish - start + 12 + (right - left)), as a float.
  CHECK_FALSE(soda::race_ends(lane, 10000, 10002, 49990.5, 50000.7, o));
  REQUIRE(soda::race_ends(lane, 10000, 10003, 49990.5, 50000.7, o));
  CHECK_FALSE(o.finished);
  CHECK(o.result == static_cast<double>(static_cast<float>(10000.0 + 667.0 / 673.0)));
}

namespace {

std::string race_text(const std::string& head, const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<race " + head + ">\n" + body + "</race>\n";
}

const char* const kTerrain =
    "<terrain filter=\"racer.FilterFixedBars\"><model><container width=\"651\" height=\"422\"/><nodes>"
    "<node id=\"n0\" x=\"0.0\" y=\"10.0\"/><node id=\"n1\" x=\"651.0\" y=\"10.0\"/></nodes>"
    "<links><fixedbar a=\"n0\" b=\"n1\"/></links></model></terrain>\n";

std::string race_error_of(const std::string& text) {
  try {
    (void)soda::read_race_text(text, "bad.xml");
  } catch (const soda::InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST_CASE("bad race files: errors name file, line, column, element, attribute, expected and got", "[race]") {
  const std::string timeout = "<timeout value=\"10000\"/>\n";
  CHECK(race_error_of(race_text("racer=\"racer.Racer\"", timeout + kTerrain)).empty());
  std::string e = race_error_of(race_text("racer=\"racer.Racer\"", timeout));
  CHECK_THAT(e, Catch::Contains("bad.xml:2:") && Catch::Contains("<race") && Catch::Contains("terrain"));
  e = race_error_of(race_text("racer=\"my.Racer\"", timeout + kTerrain));
  CHECK_THAT(e, Catch::Contains("racer") && Catch::Contains("'racer.Racer'") && Catch::Contains("'my.Racer'"));
  e = race_error_of(race_text("", "<timeout value=\"-5\"/>\n" + std::string(kTerrain)));
  CHECK_THAT(e, Catch::Contains("bad.xml:3:") && Catch::Contains("value") && Catch::Contains("'-5'"));
  e = race_error_of(race_text("", "<timeout value=\"100000000\"/>\n" + std::string(kTerrain)));
  CHECK_THAT(e, Catch::Contains("expected an integer in [1, 49997]"));
  e = race_error_of(race_text("", timeout + kTerrain + "<race_constraints><wave speed=\"BOTH\"/></race_constraints>\n"));
  CHECK_THAT(e, Catch::Contains("bad.xml:5:") && Catch::Contains("speed") && Catch::Contains("CONTENDER or RACER") &&
                    Catch::Contains("'BOTH'"));
  std::string terrain = kTerrain;
  terrain.replace(terrain.find("racer.FilterFixedBars"), 21, "racer.FilterOther");
  e = race_error_of(race_text("", timeout + terrain));
  CHECK_THAT(e, Catch::Contains("filter") && Catch::Contains("'racer.FilterOther'"));
  terrain = kTerrain;
  terrain.replace(terrain.find("x=\"651.0\""), 9, "x=\"3e9\"");
  e = race_error_of(race_text("", timeout + terrain));
  CHECK_THAT(e, Catch::Contains("terrain at most"));
  // A contender with only fixed nodes (so one last in <nodes>): no result, as the
  // racer's filter fails; the reason names it.
  const soda::RaceDef race = soda::read_race_text(race_text("", timeout + kTerrain), "ok.xml");
  soda::ModelDef fixed_only;
  fixed_only.nodes.push_back({"n0", true, 0.0, 0.0, 0.0, 0.0});
  fixed_only.nodes.push_back({"n1", true, 10.0, 0.0, 0.0, 0.0});
  fixed_only.links.push_back({soda::LinkKind::Spring, 0, 1, 10.0, 0.0, 0.0});
  CHECK_THROWS_WITH(soda::build_lane(race.terrain, race.constraints, fixed_only, "c.xml"),
                    Catch::Contains("c.xml") && Catch::Contains("no result") && Catch::Contains("'n1'"));
}

// The furthest least x of a race (RaceOutcome::furthest_min_x, what the search's
// progress score credits): the most, over the rows of the original racer's golden
// trace, of the least x of the contender's masses. Every runner keeps it: the
// reference step, the fast stepper, and the races run together in fused scenes.
TEST_CASE("race progress: the furthest least x equals the golden trace's, by every runner", "[race][golden]") {
  std::deque<soda::RaceLane> lanes; // stable addresses for LaneRace
  std::deque<soda::Model> models;
  std::vector<double> golden;
  std::vector<int> timeouts;
  std::vector<long long> last_frames;
  for (const LaneCase& k : lane_cases()) {
    const std::vector<GoldenRow> trace = lane_trace(k.name);
    lanes.push_back(lane_for(k.race, k.contender));
    models.push_back(soda::build_lane_model(lanes.back()));
    double furthest = -INFINITY;
    for (const GoldenRow& row : trace) {
      double least = INFINITY;
      for (int m = 0; m < models.back().mass_count; ++m) least = std::min(least, row.values[4 * static_cast<std::size_t>(m)]);
      furthest = std::max(furthest, least);
    }
    const long long last_frame = static_cast<long long>(trace.size()) - 1;
    golden.push_back(furthest);
    // A timeout T ends the race after update T + 3 at the latest: the trace's last
    // row (where flat_m2 finishes, the others time out).
    timeouts.push_back(static_cast<int>(last_frame) - 3);
    last_frames.push_back(last_frame);
  }
  REQUIRE(golden.size() == 8);
  std::vector<soda::State> states;
  std::vector<soda::LaneRace> races;
  for (std::size_t i = 0; i < lanes.size(); ++i) states.push_back(soda::make_state(models[i]));
  for (std::size_t i = 0; i < lanes.size(); ++i) races.push_back({&lanes[i], &models[i], timeouts[i], &states[i]});
  const std::vector<soda::RaceOutcome> together = soda::run_races_together(races);
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    INFO("lane " << i << ": golden furthest least x " << golden[i]);
    const soda::RaceOutcome reference = soda::run_race(lanes[i], models[i], timeouts[i]);
    REQUIRE(reference.updates == last_frames[i]); // the race ends on the trace's last row: every row raced
    soda::State alone = soda::make_state(models[i]);
    const soda::RaceOutcome fast = soda::run_race_fast(lanes[i], models[i], timeouts[i], alone);
    CHECK(same_bits(reference.furthest_min_x, golden[i]));
    CHECK(same_bits(fast.furthest_min_x, golden[i]));
    CHECK(same_bits(together[i].furthest_min_x, golden[i]));
  }
}
