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
  CHECK(our_result("walker_313", [](soda::FixedBars& b) { b.side_rule = soda::SideRule::Stored; }) != golden);
}
