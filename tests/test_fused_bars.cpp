// Issue 27: fixed bars in fused scenes. Different creatures, each with its own bars
// (a race lane's terrain is part of its lane model), stepped in one FusedScene must
// each equal soda::run of its model alone, bar memory included (compare_states
// compares it); races of different contenders run together (run_races_together) must
// give what run_race_fast gives each alone.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "core/batch_step.hpp"
#include "core/fused/fused_scene.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "core/race_lane.hpp"
#include "core/simd_level.hpp"
#include "core/step.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;

namespace {

/// A bundled creature in the lane of a bundled terrain, as the racer places it.
struct Lane {
  std::string name;
  soda::RaceLane lane;
  soda::Model model;
};

Lane lane_of(const std::string& creature, const std::string& terrain) {
  const soda::RaceDef race = soda::read_race_file(models_dir() / "terrains" / (terrain + ".xml"));
  Lane l;
  l.name = creature + " on " + terrain;
  l.lane = soda::build_lane(race.terrain, race.constraints, soda::read_model_file(models_dir() / creature).def, creature);
  l.model = soda::build_lane_model(l.lane);
  return l;
}

/// Six lanes of five creatures on five terrains (flat, hilly, the AI forum's, a race
/// file, a hill of the curriculum), each one where the creature lies on bars within
/// 1,200 frames (on some terrains the racer's box rule lets a creature fall through).
std::vector<Lane> some_lanes() {
  const std::pair<const char*, const char*> picks[] = {
      {"dainty_walker.xml", "TerrainFlat"}, {"wodka_ga109.xml", "TerrainFlat"}, {"carefulslug.xml", "TerrainHilly"},
      {"treader.xml", "TerrainAi"},        {"wodka_m1.xml", "TerrainHilly"},  {"carefulslug.xml", "inc1_2"}};
  std::vector<Lane> lanes;
  for (const auto& [creature, terrain] : picks) lanes.push_back(lane_of(creature, terrain));
  return lanes;
}

} // namespace

TEST_CASE("fused bars: different creatures in lanes of different terrains, one without bars, some jittered, equal "
          "the reference, bar memory included",
          "[fused_bars][race]") {
  const std::vector<Lane> lanes = some_lanes();
  const soda::Model plain = load_scene(models_dir() / "dainty_walker.xml").model; // no bars, in the middle
  REQUIRE(plain.bar_count() == 0);
  std::vector<const soda::Model*> models;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    REQUIRE(lanes[k].model.bar_count() > 0);
    models.push_back(&lanes[k].model);
    if (k == 2) models.push_back(&plain);
  }
  constexpr long long kFrames = 1200; // they fall onto their platforms and walk on
  // Every instruction set this CPU has: lanes of 2, 4 and 8 masses map differently.
  for (const soda::SimdLevel level : {soda::SimdLevel::Sse2, soda::SimdLevel::Avx2, soda::SimdLevel::Avx512}) {
    if (!soda::simd_level_supported(level)) continue;
    INFO("SIMD level " << static_cast<int>(level));
    std::vector<soda::State> states;
    for (std::size_t k = 0; k < models.size(); ++k) {
      states.push_back(soda::make_state(*models[k]));
      if (k % 2 == 1) states.back().jitter = {100 + k, 0.02};
    }
    soda::FastStepOptions options;
    options.simd = level;
    soda::FusedScene scene(models, kFrames, options);
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    // Stepped 20 frames at a time, noting which creatures a bar remembered meanwhile.
    std::vector<bool> on_bars(models.size(), false);
    const std::string diff = compare_in_pieces(models, states, kFrames, [&](long long n) {
      for (long long done = 0; done < n; done += 20) {
        scene.run(pointers.data(), std::min(20LL, n - done));
        for (std::size_t k = 0; k < states.size(); ++k) {
          on_bars[k] = on_bars[k] || !states[k].bar_memory.contacts.empty();
        }
      }
    });
    INFO(diff);
    CHECK(diff.empty());
    // The bars acted: a bar remembered every lane's creature at some time.
    for (std::size_t k = 0; k < models.size(); ++k) {
      INFO("entry " << k);
      CHECK(on_bars[k] == (models[k] != &plain));
    }
    CHECK(scene.bar_rules_run() > 100 * static_cast<long long>(lanes.size()));
  }
}

TEST_CASE("fused bars: BatchStepper fuses models with bars, apart from those without", "[fused_bars][batch_step]") {
  const std::vector<Lane> lanes = some_lanes();
  const soda::Model plain = load_scene(models_dir() / "dainty_walker.xml").model;
  const soda::Model slug = load_scene(models_dir() / "carefulslug.xml").model;
  const std::vector<const soda::Model*> models = {&lanes[0].model, &plain, &lanes[3].model, &slug, &lanes[4].model};
  std::vector<soda::State> states;
  for (const soda::Model* m : models) states.push_back(soda::make_state(*m));
  soda::BatchStepper batch(models, 800);
  CHECK(batch.fused_count() == 5);
  CHECK(batch.scene_count() == 2); // the three lanes, the two without bars
  std::vector<soda::State*> pointers;
  for (soda::State& s : states) pointers.push_back(&s);
  const std::string diff = compare_in_pieces(models, states, 800, [&](long long n) { batch.run(pointers, n); });
  INFO(diff);
  CHECK(diff.empty());
}

TEST_CASE("fused bars: races of different contenders run together give run_race_fast's outcomes and final states",
          "[fused_bars][race]") {
  std::vector<Lane> lanes = some_lanes();
  lanes.push_back(lane_of("wodka_ga109.xml", "TerrainFlat")); // a twin, jittered below
  // Short timeouts, different per race, so that some finish (wodka's racer takes
  // 118 frames on TerrainFlat) and some time out, at different updates.
  const int timeouts[] = {300, 400, 250, 350, 200, 450, 380};
  std::vector<soda::State> alone, together;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    alone.push_back(soda::make_state(lanes[k].model));
    if (k >= 4) alone.back().jitter = {7 + k, 0.05};
    if (k == 2) soda::run(lanes[k].model, alone.back(), 60); // partway: it goes on from update 60
    together.push_back(alone.back());
  }
  std::vector<soda::RaceOutcome> expected;
  std::vector<soda::LaneRace> races;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    expected.push_back(soda::run_race_fast(lanes[k].lane, lanes[k].model, timeouts[k], alone[k]));
    races.push_back({&lanes[k].lane, &lanes[k].model, timeouts[k], &together[k]});
  }
  const std::vector<soda::RaceOutcome> got = soda::run_races_together(races);
  REQUIRE(got.size() == lanes.size());
  int finished = 0;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    INFO(lanes[k].name << ", timeout " << timeouts[k]);
    CHECK(same_bits(got[k].result, expected[k].result));
    CHECK(got[k].finished == expected[k].finished);
    CHECK(got[k].updates == expected[k].updates);
    CHECK(together[k].frame == alone[k].frame);
    CHECK(compare_states(lanes[k].model, alone[k], together[k]).empty());
    finished += expected[k].finished ? 1 : 0;
  }
  // The test could fail: the races ended at different updates, some finished and some not.
  CHECK(finished > 0);
  CHECK(finished < static_cast<int>(lanes.size()));
  std::vector<long long> updates;
  for (const soda::RaceOutcome& o : expected) updates.push_back(o.updates);
  std::sort(updates.begin(), updates.end());
  CHECK(std::unique(updates.begin(), updates.end()) - updates.begin() >= 4);
}

TEST_CASE("fused bars: run_until stops each creature at its own frame and can hand the rest on", "[fused_bars]") {
  const std::vector<Lane> lanes = some_lanes();
  std::vector<const soda::Model*> models;
  for (const Lane& l : lanes) models.push_back(&l.model);
  const std::size_t n = models.size();
  constexpr long long kFrames = 600;
  // Creature c stops after 100 + 90 c frames (counted by its calls); the last never does.
  std::vector<long long> calls(n, 0);
  const auto stop = [&](int c, double, double) { return c + 1 < static_cast<int>(n) && ++calls[c] >= 100 + 90 * c; };
  std::vector<soda::State> expected, states;
  for (std::size_t c = 0; c < n; ++c) {
    expected.push_back(soda::make_state(*models[c]));
    states.push_back(expected.back());
    soda::run(*models[c], expected[c], c + 1 < n ? 100 + 90 * static_cast<long long>(c) : kFrames);
  }
  std::vector<soda::State*> pointers;
  for (soda::State& s : states) pointers.push_back(&s);
  soda::FusedScene scene(models, kFrames);
  std::vector<long long> done;
  std::vector<bool> stopped;
  // Returns once fewer than 3 run (after creature 3 stops at frame 370).
  const long long ran = scene.run_until(pointers.data(), kFrames, stop, done, stopped, 3);
  CHECK(ran == 370);
  for (std::size_t c = 0; c < n; ++c) {
    INFO("creature " << c);
    CHECK(stopped[c] == (c <= 3));
    CHECK(done[c] == (c <= 3 ? 100 + 90 * static_cast<long long>(c) : 370));
    CHECK(states[c].frame == done[c]);
    if (c <= 3) CHECK(compare_states(*models[c], expected[c], states[c]).empty());
  }
  // Parked creatures took no bar rules: a twin scene that runs all six to frame
  // 370 runs more of them.
  {
    std::vector<soda::State> twin_states;
    std::vector<soda::State*> twin;
    for (const soda::Model* m : models) twin_states.push_back(soda::make_state(*m));
    for (soda::State& s : twin_states) twin.push_back(&s);
    soda::FusedScene unparked(models, kFrames);
    unparked.run(twin.data(), 370);
    CHECK(scene.bar_rules_run() < unparked.bar_rules_run());
  }
  // The scene runs other states after parking (every creature's bar rules again),
  // then all of them stopping on their first frame.
  {
    std::vector<soda::State> fresh, reference;
    std::vector<soda::State*> fresh_pointers;
    for (const soda::Model* m : models) fresh.push_back(soda::make_state(*m));
    reference = fresh;
    for (soda::State& s : fresh) fresh_pointers.push_back(&s);
    scene.run(fresh_pointers.data(), 200);
    for (std::size_t c = 0; c < n; ++c) {
      soda::run(*models[c], reference[c], 200);
      INFO("creature " << c << " after parking");
      CHECK(compare_states(*models[c], reference[c], fresh[c]).empty());
    }
    const auto at_once = [](int, double, double) { return true; };
    CHECK(scene.run_until(fresh_pointers.data(), kFrames, at_once, done, stopped) == 1);
    CHECK(done == std::vector<long long>(n, 1));
    for (std::size_t c = 0; c < n; ++c) {
      soda::run(*models[c], reference[c], 1);
      CHECK(compare_states(*models[c], reference[c], fresh[c]).empty());
    }
  }
  // The rest go on in a scene of their own, to the end.
  std::vector<const soda::Model*> rest = {models[4], models[5]};
  std::vector<soda::State*> rest_states = {pointers[4], pointers[5]};
  soda::FusedScene smaller(rest, kFrames);
  smaller.run_until(rest_states.data(), kFrames - 370, [&](int c, double, double) { return c == 0 && ++calls[4] >= 460; },
                    done, stopped);
  CHECK(done == std::vector<long long>{90, kFrames - 370});
  CHECK(compare_states(*models[4], expected[4], states[4]).empty());
  CHECK(compare_states(*models[5], expected[5], states[5]).empty());
}
