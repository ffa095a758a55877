// Bar rules inferred from the golden race results alone (races.tsv; there is no
// trace of the original for these lanes): each was found where one contender's
// race on TerrainAi differed, and is bounded only by that race and by the other
// golden sets, which it keeps. Each test races that contender with the rule (the
// default) and with the rule's earlier form: the original's result only with the rule.
#include <catch2/catch.hpp>

#include <functional>
#include <string>

#include "bench/golden_races.hpp"
#include "core/race_lane.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;

namespace {

const char* const kTerrainAi = "soda/wwagner4_wodka/lib_wodka_jar/terrain/TerrainAi.xml";

/// The original's result for `contender` on TerrainAi (races.tsv).
double golden_result(const std::string& contender) {
  const auto rows = sodaevo::bench::race_golden(data_dir(), "terrain/TerrainAi.xml", "/" + contender + ".xml");
  REQUIRE(rows.size() == 1);
  return rows[0].golden;
}

/// Our result for `contender` on TerrainAi, the lane's bar rules changed by `change`.
double our_result(const std::string& contender, const std::function<void(soda::FixedBars&)>& change) {
  const soda::RaceDef race = soda::read_race_file(data_dir() / kTerrainAi);
  const soda::ModelDef c = soda::read_model_file(data_dir() / "terrain" / "contenders" / (contender + ".xml")).def;
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, c, contender);
  soda::Model model = soda::build_lane_model(lane);
  change(model.fixed_bars);
  soda::State state = soda::make_state(model);
  return soda::run_race_fast(lane, model, race.timeout, state).result;
}

} // namespace

TEST_CASE("inferred bar rule, near side: walker_313 on TerrainAi races as the original", "[race][golden][inferred]") {
  const double golden = golden_result("walker_313");
  CHECK(our_result("walker_313", [](soda::FixedBars&) {}) == golden);
  // Always the remembered side: at frame 6763 a mass 2.68 px above bar 1, which
  // remembers it on side 0, is caught by the bar's extended crossing point.
  CHECK(our_result("walker_313", [](soda::FixedBars& b) { b.inferred.side_rule = soda::SideRule::Stored; }) != golden);
}

TEST_CASE("inferred bar rule, hit margin below 9.35e-5: walker_514 on TerrainAi races as the original",
          "[race][golden][inferred]") {
  const double golden = golden_result("walker_514");
  CHECK(our_result("walker_514", [](soda::FixedBars&) {}) == golden);
  // Research's 1e-4: at frame 6457 bar 0 keeps mass 1 (side -1) for a crossing point
  // 9.35e-5 px beyond its end; at 6463 the mass's move off the bar is then released.
  CHECK(our_result("walker_514", [](soda::FixedBars& b) { b.inferred.hit_margin = soda::kTweakMargin; }) != golden);
  // The bound: just above the crossing point's distance the race parts again.
  CHECK(our_result("walker_514", [](soda::FixedBars& b) { b.inferred.hit_margin = 9.3e-5; }) == golden);
  CHECK(our_result("walker_514", [](soda::FixedBars& b) { b.inferred.hit_margin = 9.4e-5; }) != golden);
}

TEST_CASE("inferred bar rule, a concave joint past the next bar's far end: walker_382 on TerrainAi races as the "
          "original",
          "[race][golden][inferred]") {
  const double golden = golden_result("walker_382");
  CHECK(our_result("walker_382", [](soda::FixedBars&) {}) == golden);
  // Put on bar 2's line 0.88 px beyond its far end (50074, 20) at frame 3307.
  CHECK(our_result("walker_382", [](soda::FixedBars& b) { b.inferred.far_end_corner = false; }) != golden);
}

// The bench's report (sodaevo bench races): its counts and frames are the data's.
TEST_CASE("bench races report: counts, situations and first updates come from the races given", "[race][bench]") {
  using sodaevo::bench::GoldenRace;
  std::vector<GoldenRace> races(3);
  races[0] = {"a/TerrainAi.xml", "x/walker_382.xml", 10000.5, 10000.5};
  races[0].situations[2] = 4;
  races[0].first_update[2] = 3307;
  races[1] = {"a/TerrainAi.xml", "x/walker_999.xml", 10000.25, 10000.75};
  races[1].situations[0] = 2;
  races[1].situations[2] = 1;
  races[1].first_update[0] = 1234;
  races[1].first_update[2] = 77;
  races[2] = {"a/TerrainFlat.xml", "x/walker_999.xml", 500.0, 500.0};
  const std::string report = sodaevo::bench::golden_races_report(races);
  INFO(report);
  CHECK(report.find("**2 of 3** races") != std::string::npos);
  CHECK(report.find("| TerrainAi.xml | 1 | 2 |") != std::string::npos);
  CHECK(report.find("| far start | 1 of 3 |") != std::string::npos);
  CHECK(report.find("| near-end miss | 0 of 3 |") != std::string::npos);
  CHECK(report.find("| far-end corner | 2 of 3 |") != std::string::npos);
  // The diagnosed contender, with the first update measured in its race.
  CHECK(report.find("| walker_382 | far-end corner | InferredBarRules::far_end_corner | TerrainAi (3307) | 1 of 1 |") !=
        std::string::npos);
  CHECK(report.find("| walker_313 | far start | SideRule::Near | - | 0 of 0 |") != std::string::npos);
  CHECK(report.find("1 differ.") != std::string::npos);
  CHECK(report.find("| TerrainAi.xml | walker_999.xml | 10000.2500 | 10000.7500 | 1234 | - | 77 | none |") !=
        std::string::npos);
  races[1].ours = races[1].golden;
  CHECK(sodaevo::bench::golden_races_report(races).find("0 differ.") != std::string::npos);
}

// The diagnosed situations, measured on our runs, at the frames where a port without
// the inferred rules first parted from the original (results/bench/races.md's
// diagnosis: walker_313 at 6763, walker_382 at 3307, walker_514 at 6463).
TEST_CASE("bench races: the diagnosed situations come up where the original's runs first differed", "[race][bench]") {
  using sodaevo::bench::BarSituation;
  const auto first = [](const char* contender, BarSituation s) {
    const auto rows = sodaevo::bench::race_golden(data_dir(), "terrain/TerrainAi.xml", contender);
    REQUIRE(rows.size() == 1);
    CHECK(rows[0].same());
    return rows[0].first_update[static_cast<int>(s)];
  };
  CHECK(first("/walker_313.xml", BarSituation::FarStart) == 6763);
  CHECK(first("/walker_382.xml", BarSituation::FarEndCorner) == 3307);
  const long long miss = first("/walker_514.xml", BarSituation::NearEndMiss);
  CHECK(miss > 0);
  CHECK(miss < 6463); // the cause comes before the first differing frame
}
