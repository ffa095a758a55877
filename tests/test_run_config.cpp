// The run configuration: defaults, every key, the bundled configs, the resolved
// round trip and the error messages (evolve/config/run_config.hpp, configs/README.md).
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/input_error.hpp"
#include "evolve/config/run_config.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using sodaevo::RunConfig;
using sodaevo::test::same_bits;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A fresh folder, removed again at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    static std::atomic<int> counter{0};
    path = sodaevo::test::fresh_temp_dir("config_" + std::to_string(counter++));
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path / name;
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
    return p;
  }
};

/// The message of the InputError parsing `text` throws ("" and a failed check if none).
std::string config_error_of(const std::string& text, const fs::path& base = fs::temp_directory_path()) {
  try {
    sodaevo::parse_run_config(text, "t.json", base);
  } catch (const soda::InputError& e) {
    return e.what();
  }
  FAIL_CHECK("no error for: " << text);
  return "";
}

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t nl = s.find('\n', start);
    out.push_back(s.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  return out;
}

const std::string kAllRandom = R"({"population": {"random_fraction": 1}})";

/// Every key of the format with a value different from its default (values
/// chosen here, not taken from the code).
std::string full_config_text() {
  return R"({
  "comment": "every key",
  "$schema": "whatever",
  "name": "full-run_1.x",
  "seed": 9007199254740992,
  "generations": 77,
  "preset": "none",
  "population": {
    "size": 31,
    "seed_models": ["seeds/a.xml", "./seeds/../seeds/b.xml"],
    "random_fraction": 0.3,
    "random": { "masses_min": 5, "masses_max": 12, "extra_links_per_mass": 2.25,
                "muscle_fraction": 0.7, "size": 99.5 }
  },
  "selection": { "tournament_size": 31, "elites": 30 },
  "crossover": { "rate": 0.125 },
  "mutation": {
    "muscle_phase": { "rate": 0.41, "sigma": 0.081 },
    "muscle_amplitude": { "rate": 0.31, "sigma": 0.11 },
    "rest_length": { "rate": 0.32, "sigma": 0.09 },
    "wave": { "rate": 0.21, "speed_sigma": 0.0031, "amplitude_sigma": 0.12 },
    "move_mass": { "rate": 0.22, "sigma": 6.5 },
    "add_link": { "rate": 0.11 },
    "remove_link": { "rate": 0.12 },
    "toggle_muscle": { "rate": 0.13 },
    "add_mass": { "rate": 0.06 },
    "remove_mass": { "rate": 0.07 },
    "world": { "rate": 0.3, "sigma": 0.2 }
  },
  "limits": { "min_masses": 4, "max_masses": 50, "max_links": 200 },
  "budget": { "evaluations": 123456, "wall_seconds": 90.5 },
  "fitness": { "frames": 3000, "settle_frames": 0, "direction": "either", "scaling": "none",
               "drop_height": 12.25 },
  "world": { "gravity": 4, "friction": 0.1, "springyness": 0.25, "surface_friction": 1,
             "surface_reflection": -1, "gravity_direction": "up",
             "evolve": ["surface_reflection", "gravity"] },
  "save": { "generation_every": 0, "checkpoint_every": 7 }
})";
}

/// The JSON pointers of every key of the format (configs/README.md), written out
/// here independently of the code's table.
const std::vector<std::string> kAllKeys = {
    "/name", "/seed", "/generations", "/crossover/rate", "/population/size",
    "/population/seed_models", "/population/random_fraction", "/population/random/masses_min",
    "/population/random/masses_max", "/population/random/extra_links_per_mass",
    "/population/random/muscle_fraction", "/population/random/size", "/selection/tournament_size",
    "/selection/elites", "/mutation/muscle_phase/rate", "/mutation/muscle_phase/sigma",
    "/mutation/muscle_amplitude/rate", "/mutation/muscle_amplitude/sigma", "/mutation/rest_length/rate",
    "/mutation/rest_length/sigma", "/mutation/wave/rate", "/mutation/wave/speed_sigma",
    "/mutation/wave/amplitude_sigma", "/mutation/move_mass/rate", "/mutation/move_mass/sigma",
    "/mutation/add_link/rate", "/mutation/remove_link/rate", "/mutation/toggle_muscle/rate",
    "/mutation/add_mass/rate", "/mutation/remove_mass/rate", "/mutation/world/rate",
    "/mutation/world/sigma", "/limits/min_masses", "/limits/max_masses", "/limits/max_links",
    "/budget/evaluations", "/budget/wall_seconds", "/fitness/frames", "/fitness/settle_frames",
    "/fitness/direction", "/fitness/scaling", "/fitness/drop_height", "/fitness/mode", "/fitness/integrator",
    "/fitness/substeps", "/fitness/divergence", "/fitness/honesty/max_change",
    "/fitness/honesty/substeps_factor", "/fitness/replicas", "/fitness/replicas_max", "/fitness/confirm",
    "/fitness/statistic",
    "/fitness/jitter", "/fitness/stability_margin_min", "/world/gravity",
    "/world/friction", "/world/springyness", "/world/surface_friction", "/world/surface_reflection",
    "/world/gravity_direction", "/world/evolve", "/save/generation_every", "/save/checkpoint_every"};

std::size_t count_leaves(const json& j) {
  if (!j.is_object()) return 1;
  std::size_t n = 0;
  for (const auto& item : j) n += count_leaves(item);
  return n;
}

} // namespace

TEST_CASE("config: defaults of an (almost) empty config", "[config]") {
  const RunConfig c = sodaevo::parse_run_config(kAllRandom, "t.json", "/nowhere");
  // The values documented in run_config.hpp and configs/README.md.
  CHECK(c.name == "run");
  CHECK(c.seed == 1);
  CHECK(c.budget.generations == 40);
  CHECK(c.crossover_rate == 0.0);
  CHECK(c.population.size == 60);
  CHECK(c.population.seed_models.empty());
  CHECK(c.population.random_fraction == 1.0);
  CHECK(c.population.random.masses_min == 4);
  CHECK(c.population.random.masses_max == 10);
  CHECK(c.population.random.extra_links_per_mass == 1.5);
  CHECK(c.population.random.muscle_fraction == 0.5);
  CHECK(c.population.random.size == 120.0);
  CHECK(c.selection.tournament_size == 3);
  CHECK(c.selection.elites == 2);
  CHECK(c.mutation.muscle_phase_rate == 0.4);
  CHECK(c.mutation.muscle_phase_sigma == 0.08);
  CHECK(c.mutation.muscle_amplitude_rate == 0.3);
  CHECK(c.mutation.muscle_amplitude_sigma == 0.1);
  CHECK(c.mutation.rest_length_rate == 0.3);
  CHECK(c.mutation.rest_length_sigma == 0.08);
  CHECK(c.mutation.wave_rate == 0.2);
  CHECK(c.mutation.wave_speed_sigma == 0.003);
  CHECK(c.mutation.wave_amplitude_sigma == 0.1);
  CHECK(c.mutation.move_mass_rate == 0.2);
  CHECK(c.mutation.move_mass_sigma == 5.0);
  CHECK(c.mutation.add_link_rate == 0.1);
  CHECK(c.mutation.remove_link_rate == 0.1);
  CHECK(c.mutation.toggle_muscle_rate == 0.1);
  CHECK(c.mutation.add_mass_rate == 0.05);
  CHECK(c.mutation.remove_mass_rate == 0.05);
  CHECK(c.mutation.world_rate == 0.1);
  CHECK(c.mutation.world_sigma == 0.05);
  CHECK(c.limits.min_masses == 3);
  CHECK(c.limits.max_masses == 40);
  CHECK(c.limits.max_links == 150);
  CHECK(c.budget.max_evaluations == 0);
  CHECK(c.budget.max_wall_seconds == 0.0);
  CHECK(c.fitness.frames == 2000);
  CHECK(c.fitness.settle_frames == 200);
  CHECK(c.fitness.direction == sodaevo::WalkDirection::Right);
  CHECK(c.fitness.scaling == sodaevo::FitnessScaling::Sodarace);
  CHECK(c.fitness.drop_height == 5.0);
  CHECK(c.fitness.confirm == 10); // configs/README.md
  CHECK(c.fitness.mode == soda::PhysicsMode::Soda);
  CHECK(c.fitness.integrator == soda::Integrator::Euler);
  CHECK(c.fitness.substeps == 1);
  CHECK(c.fitness.divergence == sodaevo::DivergenceCheck::Finite);
  CHECK(c.fitness.honesty_max_change == 0.0);
  CHECK(c.fitness.honesty_substeps_factor == 4);
  CHECK(c.world.gravity == 0.38046992);
  CHECK(c.world.friction == 0.028299415);
  CHECK(c.world.springyness == 0.5);
  CHECK(c.world.surface_friction == 0.1);
  CHECK(c.world.surface_reflection == -0.75);
  CHECK(c.world.gravity_direction == soda::GravityDirection::Down);
  CHECK(c.world.evolve.empty());
  CHECK(c.save.generation_every == 10);
  CHECK(c.save.checkpoint_every == 1);

  RunConfig expected;
  expected.population.random_fraction = 1.0;
  CHECK(c == expected);
}

TEST_CASE("config: no seed models demand random_fraction 1", "[config]") {
  const std::string e = config_error_of("{}");
  CHECK(lines_of(e).size() == 1);
  CHECK(e.rfind("t.json: /population/random_fraction: expected 1 when /population/seed_models is empty", 0) == 0);
  CHECK(e.find("got 0.5") != std::string::npos);
  CHECK_NOTHROW(sodaevo::parse_run_config(R"({"population": {"seed_models": [], "random_fraction": 1.0}})",
                                          "t.json", "/nowhere"));
}

TEST_CASE("config: every key is read", "[config]") {
  TempDir dir;
  dir.write("seeds/a.xml", "<x/>");
  dir.write("seeds/b.xml", "<x/>");
  const RunConfig c = sodaevo::parse_run_config(full_config_text(), "full.json", dir.path);
  CHECK(c.name == "full-run_1.x");
  CHECK(c.seed == 9007199254740992ULL);
  CHECK(c.budget.generations == 77);
  CHECK(c.population.size == 31);
  REQUIRE(c.population.seed_models.size() == 2);
  CHECK(fs::path(c.population.seed_models[0]) == (dir.path / "seeds" / "a.xml").lexically_normal());
  CHECK(fs::path(c.population.seed_models[1]) == (dir.path / "seeds" / "b.xml").lexically_normal());
  CHECK(fs::path(c.population.seed_models[0]).is_absolute());
  CHECK(c.population.random_fraction == 0.3);
  CHECK(c.population.random.masses_min == 5);
  CHECK(c.population.random.masses_max == 12);
  CHECK(c.population.random.extra_links_per_mass == 2.25);
  CHECK(c.population.random.muscle_fraction == 0.7);
  CHECK(c.population.random.size == 99.5);
  CHECK(c.selection.tournament_size == 31);
  CHECK(c.selection.elites == 30);
  CHECK(c.crossover_rate == 0.125);
  CHECK(c.mutation.muscle_phase_rate == 0.41);
  CHECK(c.mutation.muscle_phase_sigma == 0.081);
  CHECK(c.mutation.muscle_amplitude_rate == 0.31);
  CHECK(c.mutation.muscle_amplitude_sigma == 0.11);
  CHECK(c.mutation.rest_length_rate == 0.32);
  CHECK(c.mutation.rest_length_sigma == 0.09);
  CHECK(c.mutation.wave_rate == 0.21);
  CHECK(c.mutation.wave_speed_sigma == 0.0031);
  CHECK(c.mutation.wave_amplitude_sigma == 0.12);
  CHECK(c.mutation.move_mass_rate == 0.22);
  CHECK(c.mutation.move_mass_sigma == 6.5);
  CHECK(c.mutation.add_link_rate == 0.11);
  CHECK(c.mutation.remove_link_rate == 0.12);
  CHECK(c.mutation.toggle_muscle_rate == 0.13);
  CHECK(c.mutation.add_mass_rate == 0.06);
  CHECK(c.mutation.remove_mass_rate == 0.07);
  CHECK(c.mutation.world_rate == 0.3);
  CHECK(c.mutation.world_sigma == 0.2);
  CHECK(c.limits.min_masses == 4);
  CHECK(c.limits.max_masses == 50);
  CHECK(c.limits.max_links == 200);
  CHECK(c.budget.max_evaluations == 123456);
  CHECK(c.budget.max_wall_seconds == 90.5);
  CHECK(c.fitness.frames == 3000);
  CHECK(c.fitness.settle_frames == 0);
  CHECK(c.fitness.direction == sodaevo::WalkDirection::Either);
  CHECK(c.fitness.scaling == sodaevo::FitnessScaling::None);
  CHECK(c.fitness.drop_height == 12.25);
  CHECK(c.world.gravity == 4.0);
  CHECK(c.world.friction == 0.1);
  CHECK(c.world.springyness == 0.25);
  CHECK(c.world.surface_friction == 1.0);
  CHECK(c.world.surface_reflection == -1.0);
  CHECK(c.world.gravity_direction == soda::GravityDirection::Up);
  // Stored in canonical order whatever the file's order.
  CHECK(c.world.evolve == std::vector<std::string>{"gravity", "surface_reflection"});
  CHECK(c.save.generation_every == 0);
  CHECK(c.save.checkpoint_every == 7);
}

TEST_CASE("config: to_json has every key and round-trips", "[config]") {
  TempDir dir;
  dir.write("seeds/a.xml", "<x/>");
  dir.write("seeds/b.xml", "<x/>");
  const RunConfig c = sodaevo::parse_run_config(full_config_text(), "full.json", dir.path);
  const json j = sodaevo::to_json(c);
  for (const std::string& key : kAllKeys) {
    INFO(key);
    CHECK(j.contains(json::json_pointer(key)));
  }
  CHECK(count_leaves(j) == kAllKeys.size());
  CHECK(j["fitness"]["direction"] == "either");
  CHECK(j["fitness"]["scaling"] == "none");
  CHECK(j["world"]["gravity_direction"] == "up");
  CHECK(j["world"]["evolve"] == json::array({"gravity", "surface_reflection"}));
  CHECK(j["population"]["seed_models"][0] == (dir.path / "seeds" / "a.xml").lexically_normal().string());
  CHECK(j["seed"] == 9007199254740992ULL);

  // Parsed again from anywhere (the paths are absolute now): the same config.
  CHECK(sodaevo::parse_run_config(j.dump(2), "resolved.json", "/elsewhere") == c);
  CHECK(sodaevo::parse_run_config(j.dump(), "resolved.json", "/elsewhere") == c);

  // Defaults too, with the enum spellings of the documentation.
  const RunConfig d = sodaevo::parse_run_config(kAllRandom, "t.json", "/nowhere");
  const json jd = sodaevo::to_json(d);
  CHECK(count_leaves(jd) == kAllKeys.size());
  CHECK(jd["fitness"]["direction"] == "right");
  CHECK(jd["fitness"]["scaling"] == "sodarace");
  CHECK(jd["world"]["gravity_direction"] == "down");
  CHECK(jd["world"]["evolve"] == json::array());
  CHECK(jd["population"]["seed_models"] == json::array());
  CHECK(sodaevo::parse_run_config(jd.dump(2), "t.json", "/nowhere") == d);
}

TEST_CASE("config: doubles survive to_json and back bit for bit", "[config]") {
  // nlohmann writes doubles in the shortest form that reads back exactly.
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    double v = unit(rng);
    if (i % 3 == 1) v = std::ldexp(v, static_cast<int>(rng() % 200) - 100);
    const json back = json::parse(json(v).dump());
    INFO(json(v).dump());
    REQUIRE(same_bits(back.get<double>(), v));
  }

  RunConfig c;
  c.population.random_fraction = 1.0;
  c.world.gravity = 0.1 + 0.2;                  // 0.30000000000000004
  c.world.friction = std::nextafter(1.0, 0.0);  // the largest double below 1
  c.world.springyness = 1.0 / 3.0;
  c.world.surface_reflection = -std::nextafter(0.0, 1.0); // -denormal
  c.mutation.world_sigma = 1e-300;
  c.population.random.size = 4.9406564584124654e-324 * 3;
  c.budget.max_wall_seconds = 12345.678901234567;
  const RunConfig back = sodaevo::parse_run_config(sodaevo::to_json(c).dump(2), "t.json", "/nowhere");
  CHECK(back == c);
  CHECK(same_bits(back.world.gravity, c.world.gravity));
  CHECK(same_bits(back.world.friction, c.world.friction));
  CHECK(same_bits(back.world.surface_reflection, c.world.surface_reflection));
  CHECK(same_bits(back.population.random.size, c.population.random.size));
}

TEST_CASE("config: the sodarace preset", "[config]") {
  const std::vector<std::string> all = {"gravity", "friction", "springyness", "surface_friction",
                                        "surface_reflection"};
  auto parse = [](const std::string& text) { return sodaevo::parse_run_config(text, "t.json", "/nowhere"); };
  CHECK(parse(R"({"preset": "sodarace", "population": {"random_fraction": 1}})").world.evolve == all);
  CHECK(parse(R"({"preset": "none", "population": {"random_fraction": 1}})").world.evolve.empty());
  // An explicit /world/evolve wins over the preset, even an empty one.
  CHECK(parse(R"({"preset": "sodarace", "world": {"evolve": ["friction"]}, "population": {"random_fraction": 1}})")
            .world.evolve == std::vector<std::string>{"friction"});
  CHECK(parse(R"({"preset": "sodarace", "world": {"evolve": []}, "population": {"random_fraction": 1}})")
            .world.evolve.empty());
  const std::string e = config_error_of(R"({"preset": "Sodarace", "population": {"random_fraction": 1}})");
  CHECK(e == R"(t.json: /preset: expected one of "none" or "sodarace", got "Sodarace")");
}

TEST_CASE("config: boundary values are accepted", "[config]") {
  auto parse = [](const std::string& text) { return sodaevo::parse_run_config(text, "t.json", "/nowhere"); };
  CHECK(parse(R"({"seed": 0, "population": {"random_fraction": 1}})").seed == 0);
  CHECK(parse(R"({"seed": 9007199254740992, "population": {"random_fraction": 1}})").seed == 9007199254740992ULL);
  CHECK(parse(R"({"seed": 1e3, "population": {"random_fraction": 1}})").seed == 1000); // integral, as a float
  CHECK(parse(R"({"fitness": {"frames": 10000000}, "population": {"random_fraction": 1}})").fitness.frames == 10000000);
  CHECK(parse(R"({"population": {"size": 2, "random_fraction": 1}, "selection": {"tournament_size": 2, "elites": 1}})")
            .population.size == 2);
  const RunConfig w = parse(R"({"world": {"gravity": 0, "friction": 1, "springyness": 0.5,
      "surface_friction": 0, "surface_reflection": 0, "gravity_direction": "off"},
      "population": {"random_fraction": 1}})");
  CHECK(w.world.gravity == 0.0);
  CHECK(w.world.springyness == 0.5);
  CHECK(w.world.gravity_direction == soda::GravityDirection::Off);
  CHECK(parse(R"({"name": "a", "population": {"random_fraction": 1}})").name == "a");
  CHECK(parse("{\"name\": \"" + std::string(64, 'x') + "\", \"population\": {\"random_fraction\": 1}}").name.size() == 64);
  CHECK(parse(R"({"name": "run.v2-final_3", "population": {"random_fraction": 1}})").name == "run.v2-final_3");
}

TEST_CASE("config: one error per problem, each naming pointer, expectation and value", "[config]") {
  struct Row {
    std::string text;
    std::string line; ///< the expected error line starts with this
  };
  const std::string rf = R"("population": {"random_fraction": 1})";
  const std::vector<Row> rows = {
      // unknown keys, at any depth
      {R"({"bogus": 1, )" + rf + "}", "t.json: /bogus: unknown key (expected one of: "},
      {R"({"mutation": {"add_lnk": {"rate": 0.1}}, )" + rf + "}",
       "t.json: /mutation/add_lnk: unknown key (expected one of: "},
      {R"({"population": {"random_fraction": 1, "random": {"sise": 3}}})",
       "t.json: /population/random/sise: unknown key (expected one of: "},
      {R"({"mutation": {"add_link": {"rate": 0.1, "sigma": 0.1}}, )" + rf + "}",
       "t.json: /mutation/add_link/sigma: unknown key (expected one of: rate)"},
      {R"({"a/b~c": 1, )" + rf + "}", "t.json: /a~1b~0c: unknown key"},
      // wrong types
      {R"({"population": {"size": "abc", "random_fraction": 1}})",
       R"(t.json: /population/size: expected an integer in [2, 100000], got "abc")"},
      {R"({"crossover": {"rate": "abc"}, )" + rf + "}",
       R"(t.json: /crossover/rate: expected a number in [0, 1], got "abc")"},
      {R"({"crossover": {"rate": true}, )" + rf + "}",
       "t.json: /crossover/rate: expected a number in [0, 1], got true"},
      {R"({"crossover": {"rate": null}, )" + rf + "}",
       "t.json: /crossover/rate: expected a number in [0, 1], got null"},
      {R"({"fitness": {"frames": false}, )" + rf + "}",
       "t.json: /fitness/frames: expected an integer in [1, 10000000], got false"},
      {R"({"mutation": 3, )" + rf + "}", "t.json: /mutation: expected an object"},
      {R"({"world": [], )" + rf + "}", "t.json: /world: expected an object"},
      {"[1, 2]", "t.json: (top level): expected an object"},
      {R"({"name": 7, )" + rf + "}", "t.json: /name: expected a name of 1 to 64 characters"},
      {R"({"comment": ["a"], )" + rf + "}", R"(t.json: /comment: expected a string (ignored), got ["a"])"},
      {R"({"population": {"seed_models": "a.xml"}})",
       R"(t.json: /population/seed_models: expected an array of model file paths, got "a.xml")"},
      {R"({"population": {"seed_models": [3]}})",
       "t.json: /population/seed_models/0: expected a model file path, got 3"},
      // out of range
      {R"({"population": {"size": 1, "random_fraction": 1}})",
       "t.json: /population/size: expected an integer in [2, 100000], got 1"},
      {R"({"population": {"size": 100001, "random_fraction": 1}})",
       "t.json: /population/size: expected an integer in [2, 100000], got 100001"},
      {R"({"population": {"random_fraction": 1.5}})",
       "t.json: /population/random_fraction: expected a number in [0, 1], got 1.5"},
      {R"({"population": {"random_fraction": 1, "random": {"size": 0}}})",
       "t.json: /population/random/size: expected a number in (0, 10000], got 0"},
      {R"({"mutation": {"muscle_phase": {"sigma": 0}}, )" + rf + "}",
       "t.json: /mutation/muscle_phase/sigma: expected a number in (0, 1], got 0"},
      {R"({"mutation": {"wave": {"speed_sigma": 0.2}}, )" + rf + "}",
       "t.json: /mutation/wave/speed_sigma: expected a number in (0, 0.1], got 0.2"},
      {R"({"fitness": {"frames": 0}, )" + rf + "}",
       "t.json: /fitness/frames: expected an integer in [1, 10000000], got 0"},
      {R"({"fitness": {"drop_height": -1}, )" + rf + "}",
       "t.json: /fitness/drop_height: expected a number in [0, 1000], got -1"},
      {R"({"fitness": {"confirm": -1}, )" + rf + "}",
       "t.json: /fitness/confirm: expected an integer in [0, 100000], got -1"},
      {R"({"seed": -1, )" + rf + "}", "t.json: /seed: expected an integer in [0, 9007199254740992], got -1"},
      {R"({"seed": 9007199254740993, )" + rf + "}",
       "t.json: /seed: expected an integer in [0, 9007199254740992], got 9007199254740993"},
      {R"({"seed": 18446744073709551616, )" + rf + "}", "t.json: /seed: expected an integer in [0, 9007199254740992], got 1.8446744073709552e+19"},
      {R"({"generations": 1e300, )" + rf + "}", "t.json: /generations: expected an integer in [1, 1000000], got 1e+300"},
      {R"({"save": {"checkpoint_every": 0}, )" + rf + "}",
       "t.json: /save/checkpoint_every: expected an integer in [1, 1000000], got 0"},
      {R"({"budget": {"evaluations": -5}, )" + rf + "}", "t.json: /budget/evaluations: expected an integer in [0, "},
      {R"({"world": {"gravity": 4.5}, )" + rf + "}", "t.json: /world/gravity: expected a number in [0, 4], got 4.5"},
      {R"({"world": {"springyness": 0.51}, )" + rf + "}",
       "t.json: /world/springyness: expected a number in [0, 0.5], got 0.51"},
      {R"({"world": {"surface_reflection": 0.5}, )" + rf + "}",
       "t.json: /world/surface_reflection: expected a number in [-1, 0], got 0.5"},
      {R"({"world": {"friction": -0.1}, )" + rf + "}", "t.json: /world/friction: expected a number in [0, 1], got -0.1"},
      // non-integers for integer keys
      {R"({"population": {"size": 2.5, "random_fraction": 1}})",
       "t.json: /population/size: expected an integer in [2, 100000], got 2.5"},
      {R"({"selection": {"elites": 1.0000001}, )" + rf + "}", "t.json: /selection/elites: expected an integer in [0, "},
      // enums and names
      {R"({"fitness": {"direction": "up"}, )" + rf + "}",
       R"(t.json: /fitness/direction: expected one of "right", "left" or "either", got "up")"},
      {R"({"fitness": {"scaling": 1}, )" + rf + "}", "t.json: /fitness/scaling: expected one of "},
      {R"({"world": {"gravity_direction": "sideways"}, )" + rf + "}",
       "t.json: /world/gravity_direction: expected one of "},
      {R"({"name": "my run", )" + rf + "}", R"(t.json: /name: expected a name of 1 to 64 characters)"},
      {R"({"name": "", )" + rf + "}", R"(t.json: /name: expected a name)"},
      {R"({"name": "..", )" + rf + "}", R"(t.json: /name: expected a name)"},
      {R"({"name": "a/b", )" + rf + "}", R"(t.json: /name: expected a name)"},
      {"{\"name\": \"" + std::string(65, 'x') + "\", " + rf + "}", "t.json: /name: expected a name"},
      // /world/evolve
      {R"({"world": {"evolve": "gravity"}, )" + rf + "}",
       R"(t.json: /world/evolve: expected an array of world parameter names, got "gravity")"},
      {R"({"world": {"evolve": ["gravity", "gravty"]}, )" + rf + "}",
       R"(t.json: /world/evolve/1: expected one of "gravity", "friction", "springyness", "surface_friction" or "surface_reflection", got "gravty")"},
      {R"({"world": {"evolve": ["friction", "gravity", "friction"]}, )" + rf + "}",
       R"(t.json: /world/evolve/2: expected a world parameter not listed before, got "friction")"},
      // rules between keys
      {R"({"selection": {"tournament_size": 61}, )" + rf + "}",
       "t.json: /selection/tournament_size: expected an integer in [1, 60] (at most /population/size), got 61"},
      {R"({"population": {"size": 10, "random_fraction": 1}, "selection": {"elites": 10}})",
       "t.json: /selection/elites: expected an integer in [0, 9] (less than /population/size), got 10"},
      {R"({"population": {"random_fraction": 1, "random": {"masses_min": 12}}})",
       "t.json: /population/random/masses_min: expected an integer in [3, 10] "},
      {R"({"population": {"random_fraction": 1, "random": {"masses_min": 2}}})",
       "t.json: /population/random/masses_min: expected an integer in [3, 10] "},
      {R"({"population": {"random_fraction": 1, "random": {"masses_max": 41}}})",
       "t.json: /population/random/masses_max: expected an integer in [2, 40] (at most /limits/max_masses), got 41"},
      {R"({"limits": {"min_masses": 3, "max_masses": 2}, "population": {"random_fraction": 1, "random": {"masses_min": 2, "masses_max": 2}}})",
       "t.json: /limits/min_masses: expected an integer in [2, 2] (at most /limits/max_masses), got 3"},
      {R"({"limits": {"max_links": 8}, )" + rf + "}", "t.json: /limits/max_links: expected an integer in [9, 100000]"},
      {R"({"population": {"random_fraction": 0.99}})",
       "t.json: /population/random_fraction: expected 1 when /population/seed_models is empty"},
      // duplicate keys
      {R"({"seed": 1, "seed": 2, )" + rf + "}", "t.json: /seed: duplicate key"},
      {R"({"mutation": {"wave": {"rate": 0.1, "rate": 0.2}}, )" + rf + "}", "t.json: /mutation/wave/rate: duplicate key"},
      {R"({"world": {"evolve": [{"a": 1, "a": 2}]}, )" + rf + "}", "t.json: /world/evolve/0/a: duplicate key"},
  };
  for (const Row& row : rows) {
    INFO(row.text);
    const std::string e = config_error_of(row.text);
    INFO(e);
    const auto lines = lines_of(e);
    // The /world/evolve duplicate-key row also reports the element itself.
    const std::size_t expected_lines = row.text.find("\"a\": 1, \"a\"") != std::string::npos ? 2 : 1;
    CHECK(lines.size() == expected_lines);
    CHECK(lines[0].rfind(row.line, 0) == 0);
  }
}

TEST_CASE("config: unknown keys come with a suggestion", "[config]") {
  const std::string e = config_error_of(R"({"mutation": {"add_lnk": {"rate": 0.1}}, "population": {"random_fraction": 1}})");
  for (const char* op : {"muscle_phase", "muscle_amplitude", "rest_length", "wave", "move_mass", "add_link",
                         "remove_link", "toggle_muscle", "add_mass", "remove_mass", "world"}) {
    CHECK(e.find(op) != std::string::npos);
  }
  CHECK(e.find("did you mean \"add_link\"?") != std::string::npos);
  CHECK(config_error_of(R"({"zzzzzzzz": 1, "population": {"random_fraction": 1}})").find("did you mean") == std::string::npos);
}

TEST_CASE("config: all errors are reported together", "[config]") {
  const std::string e = config_error_of(R"({
    "seed": -1,
    "population": {"size": 1, "random_fraction": 2},
    "mutation": {"add_lnk": {}},
    "world": {"gravity": "x", "evolve": ["gravity", "nope"]},
    "fitness": {"frames": 2.5}
  })");
  const auto lines = lines_of(e);
  INFO(e);
  CHECK(lines.size() == 7);
  for (const char* p : {"t.json: /seed: ", "t.json: /population/size: ", "t.json: /population/random_fraction: ",
                        "t.json: /mutation/add_lnk: ", "t.json: /world/gravity: ", "t.json: /world/evolve/1: ",
                        "t.json: /fitness/frames: "}) {
    INFO(p);
    CHECK(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.rfind(p, 0) == 0; }) == 1);
  }
}

TEST_CASE("config: JSON syntax errors give line and column", "[config]") {
  CHECK(config_error_of("{\n  \"seed\": 1,\n  \"name\": \n}").rfind("t.json:4:1: ", 0) == 0);
  CHECK(config_error_of("{\r\n  \"seed\": 1,\r\n  \"name\" 3\r\n}").rfind("t.json:3:10: ", 0) == 0);
  CHECK(config_error_of("{\"seed\": 1").rfind("t.json:1:11: ", 0) == 0); // end of input
  CHECK(config_error_of("").rfind("t.json:1:1: ", 0) == 0);
  CHECK(config_error_of("{\n  \"a\": 1,\n  \"b\": [1, 2,, 3]\n}").rfind("t.json:3:14: ", 0) == 0);
  // A number too large for a double: nlohmann reports no position; we find it.
  const std::string big = config_error_of("{\n  \"comment\": \"1e999\",\n  \"seed\": 1e999\n}");
  CHECK(big.rfind("t.json:3:11: ", 0) == 0);
  CHECK(big.find("1e999") != std::string::npos);
  // Comments are not JSON.
  CHECK(config_error_of("{\n  // a comment\n  \"seed\": 1\n}").rfind("t.json:2:", 0) == 0);
}

TEST_CASE("config: read_run_config resolves and checks seed models", "[config]") {
  TempDir dir;
  dir.write("models/walker.xml", "<x/>");
  dir.write("shared/other.xml", "<x/>");
  const fs::path other = (dir.path / "shared" / "other.xml").lexically_normal();
  const fs::path config = dir.write("configs/run.json", R"({
  "population": {"seed_models": ["../models/walker.xml", ")" + other.string() + R"("]}
})");
  const RunConfig c = sodaevo::read_run_config(config);
  REQUIRE(c.population.seed_models.size() == 2);
  CHECK(c.population.seed_models[0] == (dir.path / "models" / "walker.xml").lexically_normal().string());
  CHECK(c.population.seed_models[1] == other.string());
  CHECK(c.population.random_fraction == 0.5); // seeds given: the default applies

  // A relative config path works the same (resolved against the working folder).
  const fs::path cwd = fs::current_path();
  fs::current_path(dir.path);
  RunConfig relative;
  CHECK_NOTHROW(relative = sodaevo::read_run_config("configs/run.json"));
  fs::current_path(cwd);
  CHECK(relative == c);

  // Missing seed models: every one reported with its index.
  const fs::path bad = dir.write("configs/bad.json", R"({
  "population": {"seed_models": ["../models/walker.xml", "../models/nope.xml", "missing.xml", "../models"]}
})");
  std::string e;
  try {
    sodaevo::read_run_config(bad);
    FAIL("no error for missing seed models");
  } catch (const soda::InputError& err) {
    e = err.what();
  }
  INFO(e);
  const auto lines = lines_of(e);
  CHECK(lines.size() == 3);
  CHECK(e.find(bad.string() + ": /population/seed_models/1: expected an existing model file") != std::string::npos);
  CHECK(e.find("\"../models/nope.xml\"") != std::string::npos);
  CHECK(e.find((dir.path / "models" / "nope.xml").lexically_normal().string()) != std::string::npos);
  CHECK(e.find("/population/seed_models/2: expected an existing model file") != std::string::npos);
  CHECK(e.find("/population/seed_models/3: expected an existing model file") != std::string::npos); // a folder

  // Missing file, a folder, a syntax error: the path is named.
  const fs::path missing = dir.path / "nope.json";
  try {
    sodaevo::read_run_config(missing);
    FAIL("no error for a missing file");
  } catch (const soda::InputError& err) {
    CHECK(std::string(err.what()).rfind(missing.string() + ": ", 0) == 0);
  }
  try {
    sodaevo::read_run_config(dir.path / "configs");
    FAIL("no error for a folder");
  } catch (const soda::InputError& err) {
    CHECK(std::string(err.what()).rfind((dir.path / "configs").string() + ": ", 0) == 0);
  }
  const fs::path broken = dir.write("broken.json", "{\n  \"seed\": 1,\n  \"name\": \n}");
  try {
    sodaevo::read_run_config(broken);
    FAIL("no error for bad JSON");
  } catch (const soda::InputError& err) {
    CHECK(std::string(err.what()).rfind(broken.string() + ":4:1: ", 0) == 0);
  }
  // A UTF-8 byte order mark is allowed and does not shift columns.
  const fs::path bom = dir.write("bom.json", "\xEF\xBB\xBF{\"seed\": x}");
  try {
    sodaevo::read_run_config(bom);
    FAIL("no error for bad JSON");
  } catch (const soda::InputError& err) {
    CHECK(std::string(err.what()).rfind(bom.string() + ":1:10: ", 0) == 0);
  }
  CHECK(sodaevo::read_run_config(dir.write("bom2.json", "\xEF\xBB\xBF" + kAllRandom)).population.random_fraction == 1.0);
}

TEST_CASE("config: the bundled configs parse", "[config]") {
  const fs::path configs = fs::path(SODAEVO_MODELS_DIR).parent_path() / "configs";
  REQUIRE(fs::is_directory(configs));
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(configs)) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  CHECK(files.size() >= 4);
  for (const char* name : {"default.json", "quick.json", "long.json", "sodarace.json"}) {
    CHECK(std::find(files.begin(), files.end(), configs / name) != files.end());
  }
  for (const fs::path& file : files) {
    INFO(file.string());
    // Seed models may not be there yet: skip such a file with a warning.
    std::ifstream in(file);
    const json raw = json::parse(in);
    bool seeds_present = true;
    if (raw.contains("population") && raw["population"].contains("seed_models")) {
      for (const auto& s : raw["population"]["seed_models"]) {
        if (!fs::is_regular_file(configs / s.get<std::string>())) {
          WARN(file.filename().string() << ": seed model " << s.get<std::string>() << " is missing; skipped");
          seeds_present = false;
        }
      }
    }
    if (!seeds_present) continue;
    RunConfig c;
    REQUIRE_NOTHROW(c = sodaevo::read_run_config(file));
    CHECK(c.name == file.stem().string()); // each config names its run after itself
    for (const std::string& s : c.population.seed_models) {
      INFO(s);
      CHECK(fs::path(s).is_absolute());
      CHECK(fs::path(s).parent_path() == fs::path(SODAEVO_MODELS_DIR).lexically_normal());
      // A seed must fit the config's own limits, or it could never be mutated legally.
      soda::LoadedModel seed;
      REQUIRE_NOTHROW(seed = soda::read_model_file(s));
      CHECK(static_cast<long>(seed.def.nodes.size()) >= c.limits.min_masses);
      CHECK(static_cast<long>(seed.def.nodes.size()) <= c.limits.max_masses);
      CHECK(static_cast<long>(seed.def.links.size()) <= c.limits.max_links);
    }
    CHECK(sodaevo::parse_run_config(sodaevo::to_json(c).dump(2), "resolved.json", "/elsewhere") == c);
    const std::string stem = file.stem().string();
    if (stem == "quick") {
      CHECK(c.population.size == 24);
      CHECK(c.budget.generations == 10);
      CHECK(c.fitness.frames == 1000);
    } else if (stem == "default") {
      // As configs/README.md describes it.
      CHECK(c.population.size == 200);
      CHECK(c.budget.generations == 200);
      CHECK(c.fitness.frames == 4000);
      CHECK(c.fitness.settle_frames == 400);
    } else if (stem == "long") {
      CHECK(c.population.size == 200);
      CHECK(c.budget.generations == 300);
    } else if (stem == "sodarace") {
      CHECK(c.world.evolve.size() == 5);
    }
  }
}

TEST_CASE("config: the example of configs/README.md is valid", "[config]") {
  const fs::path configs = fs::path(SODAEVO_MODELS_DIR).parent_path() / "configs";
  std::ifstream in(configs / "README.md");
  REQUIRE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::string readme = text.str();
  int examples = 0;
  for (std::size_t at = readme.find("```json\n"); at != std::string::npos; at = readme.find("```json\n", at + 1)) {
    const std::size_t begin = at + 8;
    const std::size_t end = readme.find("```", begin);
    REQUIRE(end != std::string::npos);
    const std::string block = readme.substr(begin, end - begin);
    if (block.empty() || block[0] != '{') continue; // a fragment
    ++examples;
    INFO(block);
    if (block.find("../models/") != std::string::npos && !fs::is_directory(SODAEVO_MODELS_DIR)) continue;
    try {
      sodaevo::parse_run_config(block, "README example", configs);
    } catch (const soda::InputError& e) {
      if (std::string(e.what()).find("expected an existing model file") != std::string::npos) {
        WARN("README example: seed model missing; skipped");
        continue;
      }
      FAIL(e.what());
    }
  }
  CHECK(examples >= 1);
}

TEST_CASE("config: a seed-model pattern expands to the matching files, sorted", "[config]") {
  TempDir dir;
  // Created out of order, plus files the pattern must not take.
  dir.write("seeds/walker_c.xml", "<x/>");
  dir.write("seeds/walker_a.xml", "<x/>");
  dir.write("seeds/walker_b.xml", "<x/>");
  dir.write("seeds/notes.txt", "x");
  dir.write("seeds/other.xml", "<x/>");
  const RunConfig c = sodaevo::parse_run_config(
      R"({"population": {"seed_models": ["seeds/walker_*.xml", "seeds/other.xml"]}})", "p.json", dir.path);
  REQUIRE(c.population.seed_models.size() == 4);
  const char* expected_names[] = {"walker_a.xml", "walker_b.xml", "walker_c.xml", "other.xml"};
  for (int i = 0; i < 4; ++i) {
    CHECK(fs::path(c.population.seed_models[i]).filename() == expected_names[i]);
    CHECK(fs::path(c.population.seed_models[i]).is_absolute());
  }
  const std::string error = config_error_of(R"({"population": {"seed_models": ["seeds/none_*.xml"]}})", dir.path);
  CHECK(error.find("t.json: /population/seed_models/0: expected a pattern matching at least one model file") !=
        std::string::npos);
  CHECK(error.find("\"seeds/none_*.xml\"") != std::string::npos);
}
