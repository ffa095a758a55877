// Replica ensembles (evolve/estimators/replica_ensemble.hpp), their summary
// (evolve/estimators/sample_summary.hpp) and `simulate --replicas`.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/step.hpp"
#include "evolve/estimators/replica_ensemble.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "test_support.hpp"

using sodaevo::test::golden_dir;
using sodaevo::test::load_scene;
using sodaevo::test::run_sodaevo;
using sodaevo::test::ShellResult;

TEST_CASE("Student's t quantile matches the printed tables", "[replicas]") {
  // t(0.975, df) from a standard two-sided 5 % table.
  const std::vector<std::pair<int, double>> table = {{1, 12.706}, {2, 4.303}, {3, 3.182}, {5, 2.571},
                                                     {10, 2.228}, {15, 2.131}, {30, 2.042}, {120, 1.980}};
  for (const auto& [df, t] : table) {
    INFO("df " << df);
    CHECK(sodaevo::student_t_975(df) == Approx(t).margin(6e-4));
  }
  CHECK(sodaevo::student_t_975(1'000'000) == Approx(1.95996).margin(1e-5));
}

TEST_CASE("a sample summary: mean, median, sd, range and the prediction interval", "[replicas]") {
  const sodaevo::SampleSummary s = sodaevo::summarize_sample({10.0, 1.0, 4.0, 3.0, 2.0});
  CHECK(s.n == 5);
  CHECK(s.mean == Approx(4.0));
  CHECK(s.median == 3.0);
  CHECK(s.sd == Approx(std::sqrt(50.0 / 4.0))); // squares 36 + 9 + 0 + 1 + 4
  CHECK(s.min == 1.0);
  CHECK(s.max == 10.0);
  const double half = 2.776445 * std::sqrt(12.5) * std::sqrt(1.0 + 1.0 / 5.0);
  CHECK(s.interval95_low == Approx(4.0 - half).epsilon(1e-6));
  CHECK(s.interval95_high == Approx(4.0 + half).epsilon(1e-6));
  CHECK(sodaevo::summarize_sample({1.0, 2.0, 3.0, 4.0}).median == 2.5);
  const sodaevo::SampleSummary one = sodaevo::summarize_sample({7.0});
  CHECK((one.sd == 0.0 && one.interval95_low == 7.0 && one.interval95_high == 7.0));
  CHECK_THROWS_AS(sodaevo::summarize_sample({}), std::invalid_argument);
}

// random_26 (a golden trace's random creature) is chaotic: its jittered replicas
// part within a few hundred frames. The classic walkers (models/) are not: their
// replicas stay within 1e-9 px for 10,000 frames.
TEST_CASE("replicas: replica 0 is the exact run, the others part from it", "[replicas]") {
  const auto scene = load_scene(golden_dir() / "random_26.xml");
  sodaevo::ReplicaSettings settings;
  settings.seeds = sodaevo::consecutive_seeds(4);
  settings.settle = 100;
  settings.frames = 2000;
  const sodaevo::ReplicaResults r = sodaevo::run_replicas(scene.model, settings);
  REQUIRE(r.distances.size() == 4);
  soda::State exact = soda::make_state(scene.model);
  soda::run(scene.model, exact, 100);
  const double start = soda::mass_centroid(scene.model, exact).x;
  soda::run(scene.model, exact, 2000);
  CHECK(r.distances[0] == soda::mass_centroid(scene.model, exact).x - start);
  CHECK(r.horizon > 0);
  CHECK(r.horizon <= 2100);
  CHECK(r.distances[1] != r.distances[0]);
  CHECK(sodaevo::run_replicas(scene.model, settings).distances == r.distances); // deterministic

  // Without jitter every replica is the exact run: no horizon.
  settings.probability = 0.0;
  const sodaevo::ReplicaResults same = sodaevo::run_replicas(scene.model, settings);
  CHECK(same.horizon == -1);
  for (double d : same.distances) CHECK(d == r.distances[0]);
  settings.probability = 1.5;
  CHECK_THROWS_AS(sodaevo::run_replicas(scene.model, settings), std::invalid_argument);
}

TEST_CASE("simulate --replicas reports the distribution and the horizon", "[replicas][cli]") {
  const std::string model = (golden_dir() / "random_26.xml").string();
  ShellResult r = run_sodaevo("simulate " + model + " --replicas 5 --jitter 0.01 --settle 50 --frames 800 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"n", "mean", "median", "sd", "min", "max", "interval95", "horizon", "distances"}) {
    CHECK(j.contains(key));
  }
  CHECK(j["n"] == 5);
  CHECK(j["settle"] == 50);
  CHECK(j["interval95"].size() == 2);
  CHECK(j["interval95"][0].get<double>() <= j["mean"].get<double>());
  CHECK(j["horizon"].is_number());

  r = run_sodaevo("simulate " + model + " --replicas 3 --frames 300");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("interval95") != std::string::npos);
  CHECK(r.output.find("horizon") != std::string::npos);

  // Bad input names the option.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"--replicas 0", "--replicas"},          {"--replicas 100000", "--replicas"},
      {"--replicas 4 --jitter 1.5", "--jitter"}, {"--jitter 0.1", "--replicas"},
      {"--replicas 4 --settle -3", "--settle"},  {"--replicas 4 --trace x.csv", "--trace"}};
  for (const auto& [args, option] : bad) {
    r = run_sodaevo("simulate " + model + " " + args);
    INFO(args << ": " << r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.output.find(option) != std::string::npos);
  }
}

TEST_CASE("race --replicas gives each contender's distribution, its interval never below 0 frames", "[replicas][cli]") {
  // Contenders 2-4 of this race sometimes finish and sometimes time out under
  // jitter: a spread of thousands of frames, which mean -+ t sd takes below 0.
  const std::string race = (sodaevo::test::data_dir() / "terrain" / "race_hist_32_166.xml").string();
  ShellResult r = run_sodaevo("race " + race + " --replicas 4 --json");
  INFO(r.output.substr(0, 2000));
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output);
  REQUIRE(j["contenders"].size() == 6);
  bool wide = false;
  for (const auto& c : j["contenders"]) {
    const auto& d = c["replicas"];
    CHECK(d["n"] == 4);
    const double lo = d["interval95"][0].get<double>(), hi = d["interval95"][1].get<double>();
    CHECK(lo >= 0.0);
    CHECK(lo <= d["median"].get<double>());
    CHECK(d["median"].get<double>() <= hi);
    CHECK(d["min"].get<double>() <= d["median"].get<double>());
    wide = wide || hi - lo > 1000.0;
  }
  CHECK(wide); // the race has the spread that made intervals negative
}
