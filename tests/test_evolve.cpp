// The genetic algorithm and its run store: determinism, resume, replay, export.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/problems/creature_graph.hpp"
#include "evolve/problems/creature_limits.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "test_support.hpp"

using namespace sodaevo;
namespace fs = std::filesystem;

namespace {

RunConfig small_config() {
  RunConfig c = test::walker_run_config("test", 42, 12, 5, 400, 50);
  c.population.random_fraction = 0.5;
  c.crossover_rate = 0.3;
  c.save.generation_every = 2;
  return c;
}

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sodaevo_evolve_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  return d;
}

/// A new run in `dir` stopped (as Ctrl-C does) after generation `stop_after`.
EvolutionOutcome run_until(const fs::path& dir, const RunConfig& config, int stop_after) {
  RunStore store = RunStore::create(dir, config, false, "test");
  ThreadEvaluator evaluator(2);
  std::atomic<bool> stop{false};
  EvolutionOptions options;
  options.stop_requested = &stop;
  options.on_generation = [&](const Progress& p) {
    if (p.generation == stop_after) stop = true;
  };
  return run_evolution(store, evaluator, options);
}

fs::path run_to_end(const RunConfig& config, const std::string& name, int threads) {
  const fs::path dir = fresh_dir(name);
  RunStore store = RunStore::create(dir, config, false, "test");
  ThreadEvaluator evaluator(threads);
  run_evolution(store, evaluator, {});
  return dir;
}

std::string evolve_file_text(const fs::path& p) { return soda::read_whole_file(p); }

void require_same_evolve_results(const fs::path& a, const fs::path& b) {
  CHECK(evolve_file_text(a / "generations.csv") == evolve_file_text(b / "generations.csv"));
  const auto saved = saved_generations(a);
  REQUIRE(!saved.empty());
  CHECK(saved == saved_generations(b));
  for (int g : saved) {
    INFO("generation " << g);
    CHECK(evolve_file_text(a / "generations" / generation_file_name(g)) == evolve_file_text(b / "generations" / generation_file_name(g)));
    CHECK(evolve_file_text(a / "best" / generation_file_name(g)) == evolve_file_text(b / "best" / generation_file_name(g)));
  }
}

} // namespace

// /budget/evaluations: the run stops before a generation it has no room for (its
// children plus the final confirmation's /fitness/confirm). Worked out by hand for
// 10 creatures, 2 elites (8 children a generation), confirm 2, a budget of 43:
// spent after generations 0..3 is 10, 18, 26, 34; after 26 there is room
// (26 + 8 + 2 = 36), after 34 not (34 + 8 + 2 = 44; without the confirmation's
// reserve there would be). No resampling (replicas = replicas_max), so nothing
// else is spent.
TEST_CASE("the evaluation budget ends the run at the generation worked out by hand", "[evolve]") {
  RunConfig c = test::walker_run_config("budget", 7, 10, 100, 200, 20);
  c.selection.elites = 2;
  c.fitness.replicas = c.fitness.replicas_max = 1;
  c.fitness.confirm = 2;
  c.budget.max_evaluations = 43;
  const fs::path dir = fresh_dir("budget");
  RunStore store = RunStore::create(dir, c, false, "test");
  ThreadEvaluator evaluator(2);
  const EvolutionOutcome o = run_evolution(store, evaluator, {});
  CHECK(o.stopped_because == StopReason::EvaluationBudget);
  CHECK(o.last_generation == 3);
  CHECK(o.evaluations == 34);
  fs::remove_all(dir);
}

TEST_CASE("SplitMix64 matches the reference sequence", "[evolve]") {
  // Published test vector of SplitMix64 (Vigna's splitmix64.c) for seed 1234567.
  Rng rng(1234567);
  CHECK(rng.next_u64() == 6457827717110365317ull);
  CHECK(rng.next_u64() == 3203168211198807973ull);
  CHECK(rng.next_u64() == 9817491932198370423ull);
  CHECK(rng.next_u64() == 4593380528125082431ull);
  CHECK(rng.next_u64() == 16408922859458223821ull);
  Rng r2 = Rng::stream(1, 2, 3, 4);
  double lo = 1, hi = 0, sum = 0;
  for (int i = 0; i < 100000; ++i) {
    const double u = r2.uniform();
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    sum += u;
    const auto k = r2.below(7);
    REQUIRE(k < 7);
  }
  CHECK(lo >= 0.0);
  CHECK(hi < 1.0);
  CHECK(sum / 100000 == Approx(0.5).margin(0.01));
}

TEST_CASE("Sodarace scaling: a single spring is scaled to length 211", "[evolve]") {
  // configs/README.md, /fitness/scaling: s = 211/sqrt(sum Lmax^2); for one spring of
  // rest R, s = 211/R.
  soda::ModelDef c;
  c.nodes = {{"m0", false, 0, 0, 0, 0}, {"m1", false, 50, 0, 0, 0}};
  c.links = {{soda::LinkKind::Spring, 0, 1, 50.0, 0, 0}};
  REQUIRE(sodarace_scale(c).has_value());
  CHECK(*sodarace_scale(c) == Approx(211.0 / 50.0).epsilon(1e-15));
  c.links[0] = {soda::LinkKind::Muscle, 0, 1, 50.0, 0.5, 0.0};
  c.wave.amplitude = 0.4; // Lmax = 50*(1 + 0.5*0.4) = 60
  CHECK(*sodarace_scale(c) == Approx(211.0 / 60.0).epsilon(1e-15));
}

TEST_CASE("variation keeps creatures valid and exact through XML", "[evolve]") {
  const RunConfig config = small_config();
  for (std::uint64_t i = 0; i < 300; ++i) {
    Rng rng = Rng::stream(7, i);
    soda::ModelDef c = random_creature(config, rng);
    INFO("creature " << i);
    REQUIRE_FALSE(check_creature(c, config.limits).has_value());
    soda::ModelDef other = random_creature(config, rng);
    for (int k = 0; k < 20; ++k) {
      mutate(c, config, rng);
      if (k % 5 == 0) c = crossover(c, other, config, rng);
      REQUIRE_FALSE(check_creature(c, config.limits).has_value());
      for (const soda::LinkDef& l : c.links) {
        REQUIRE(l.amplitude >= 0.0);
        REQUIRE(l.amplitude <= 1.0);
        REQUIRE(l.phase >= 0.0);
        REQUIRE(l.phase < 1.0);
      }
    }
    REQUIRE(c == soda::canonical_form(c));
    REQUIRE(soda::read_model_text(soda::write_model_text(c), "mem").def == c);
  }
}

TEST_CASE("same config and seed: identical results with 1, 2 and 8 threads", "[evolve]") {
  const RunConfig config = small_config();
  const fs::path one = run_to_end(config, "one", 1);
  const fs::path two = run_to_end(config, "two", 2);
  const fs::path eight = run_to_end(config, "eight", 8);
  require_same_evolve_results(one, two);
  require_same_evolve_results(one, eight);
  // The run must have done something worth comparing.
  const std::string csv = evolve_file_text(one / "generations.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + config.budget.generations);
  fs::remove_all(one.parent_path());
}

TEST_CASE("an interrupted run resumes to exactly the uninterrupted result", "[evolve]") {
  RunConfig config = small_config();
  config.save.generation_every = 1;
  const fs::path whole = run_to_end(config, "whole", 2);

  const fs::path dir = fresh_dir("interrupted");
  {
    const EvolutionOutcome o = run_until(dir, config, 2);
    CHECK(o.stopped_because == StopReason::Interrupted);
    CHECK(o.last_generation == 2);
  }
  {
    RunStore store = RunStore::open(dir);
    // The run folder carries its seed model; the rest of the config is as given.
    RunConfig expected = config;
    expected.population.seed_models = {(fs::absolute(dir) / "seeds" / "dainty_walker.xml").lexically_normal().string()};
    CHECK(store.config() == expected);
    ThreadEvaluator evaluator(1);
    const EvolutionOutcome o = run_evolution(store, evaluator, {});
    CHECK(o.stopped_because == StopReason::Completed);
  }
  require_same_evolve_results(whole, dir);
  fs::remove_all(dir.parent_path());
}

TEST_CASE("a run folder is self-contained: moved away from its seed models it is read, replayed and resumed",
          "[evolve]") {
  // The seed model lives in a folder of its own, which is deleted after the run
  // started: the run folder must not need it (it keeps a copy in seeds/).
  const fs::path base = fresh_dir("moved");
  fs::create_directories(base / "mine");
  fs::copy_file(fs::path(SODAEVO_MODELS_DIR) / "dainty_walker.xml", base / "mine" / "dainty_walker.xml");
  RunConfig config = small_config();
  config.budget.generations = 3;
  config.save.generation_every = 1;
  config.population.seed_models = {(base / "mine" / "dainty_walker.xml").string()};
  CHECK(run_until(base / "run", config, 1).stopped_because == StopReason::Interrupted);
  CHECK(soda::read_whole_file(base / "run" / "seeds" / "dainty_walker.xml") ==
        soda::read_whole_file(fs::path(SODAEVO_MODELS_DIR) / "dainty_walker.xml"));
  CHECK(nlohmann::json::parse(soda::read_whole_file(base / "run" / "config.json"))["population"]["seed_models"] ==
        nlohmann::json::array({"seeds/dainty_walker.xml"}));
  fs::remove_all(base / "mine");
  fs::rename(base / "run", base / "moved_run");
  const fs::path moved = base / "moved_run";
  REQUIRE_NOTHROW(read_run_config(moved / "config.json"));
  // Resumed where it was moved to, the run ends as one that was never interrupted
  // nor moved.
  {
    RunStore store = RunStore::open(moved);
    ThreadEvaluator evaluator(1);
    CHECK(run_evolution(store, evaluator, {}).stopped_because == StopReason::Completed);
  }
  RunConfig plain = small_config();
  plain.budget.generations = 3;
  plain.save.generation_every = 1;
  const fs::path whole = run_to_end(plain, "moved_whole", 2);
  require_same_evolve_results(whole, moved);
  // Replayed there: every saved creature gives its logged fitness.
  const RunConfig read_back = read_run_config(moved / "config.json");
  for (int g : saved_generations(moved)) {
    for (const Individual& ind : read_saved_generation(moved, g).individuals) {
      CHECK(evaluate_creature(ind.creature, read_back, ind.evaluation.estimate.rollouts).fitness ==
            ind.evaluation.fitness);
    }
  }
  fs::remove_all(base);
}

TEST_CASE("replay and export reproduce the logged fitness exactly", "[evolve]") {
  const RunConfig config = small_config();
  const fs::path dir = run_to_end(config, "replay", 2);
  int checked = 0;
  for (int g : saved_generations(dir)) {
    const Generation gen = read_saved_generation(dir, g);
    for (const Individual& ind : gen.individuals) {
      // On as many replicas as it was logged with (survivors gather more).
      const Evaluation again = evaluate_creature(ind.creature, config, ind.evaluation.estimate.rollouts);
      REQUIRE(again.status == ind.evaluation.status);
      if (again.ok()) REQUIRE(again.fitness == ind.evaluation.fitness);
      ++checked;
    }
  }
  CHECK(checked >= 2 * config.population.size);
  // Exported (prepared) XML, read back and simulated, scores the logged fitness.
  for (const Individual& ind : best_individuals(dir, 3)) {
    const soda::ModelDef prepared = walk_problem_of(config).prepare(ind.creature);
    const fs::path out = dir / (ind.id + ".xml");
    soda::write_model_file(out, prepared);
    const soda::ModelDef reloaded = soda::read_model_file(out).def;
    const Evaluation e = walk_problem_of(config).rollouts({&reloaded}).front();
    REQUIRE(e.ok());
    // One exact rollout of the export is the logged estimate's replica 0.
    CHECK(e.distance == ind.evaluation.distance);
    // And with the plain reference step (what the original runs), not the fast
    // stepper the GA uses: settle, then the centroid's displacement.
    const soda::Model model = soda::build_model(reloaded);
    soda::State state = soda::make_state(model);
    soda::run(model, state, config.fitness.settle_frames);
    const double start_x = soda::mass_centroid(model, state).x;
    soda::run(model, state, config.fitness.frames);
    CHECK(soda::mass_centroid(model, state).x - start_x == ind.evaluation.distance);
  }
  fs::remove_all(dir.parent_path());
}

TEST_CASE("an existing run folder is refused without --force", "[evolve]") {
  const RunConfig config = small_config();
  const fs::path dir = fresh_dir("exists");
  RunStore::create(dir, config, false, "test");
  CHECK_THROWS_WITH(RunStore::create(dir, config, false, "test"), Catch::Contains("exists already"));
  CHECK_NOTHROW(RunStore::create(dir, config, true, "test"));
  fs::remove_all(dir.parent_path());
}

TEST_CASE("batch and single evaluation give identical Evaluations", "[evolve]") {
  RunConfig config = small_config();
  config.fitness.replicas = config.fitness.replicas_max = 1; // evaluate_creature as one exact rollout
  config.world.evolve = {"friction", "surface_reflection"};
  std::vector<soda::ModelDef> creatures;
  creatures.push_back(soda::read_model_file(test::models_dir() / "dainty_walker.xml").def);
  for (std::uint64_t i = 0; i < 20; ++i) {
    Rng rng = Rng::stream(99, i);
    soda::ModelDef c = random_creature(config, rng);
    c.environment.friction = 0.005 * static_cast<double>(i % 6);
    creatures.push_back(c);
  }
  soda::ModelDef invalid = creatures[1];
  invalid.links.clear();
  creatures.insert(creatures.begin() + 3, invalid);
  creatures.push_back(creatures[2]); // a duplicate
  // Children of the Dainty Walker that keep its shape: a batch holding six or
  // more of them steps them in lockstep (soda::LockstepBatch) on AVX-512.
  RunConfig keep_shape = config;
  keep_shape.mutation.add_link_rate = keep_shape.mutation.remove_link_rate = 0.0;
  keep_shape.mutation.add_mass_rate = keep_shape.mutation.remove_mass_rate = 0.0;
  keep_shape.mutation.toggle_muscle_rate = 0.0;
  for (std::uint64_t i = 0; i < 7; ++i) {
    Rng rng = Rng::stream(7, i);
    soda::ModelDef child = creatures[0];
    mutate(child, keep_shape, rng);
    creatures.insert(creatures.begin() + static_cast<std::ptrdiff_t>(2 + 3 * i), child);
  }
  std::vector<const soda::ModelDef*> ptrs;
  for (const soda::ModelDef& c : creatures) ptrs.push_back(&c);
  auto same = [](const Evaluation& a, const Evaluation& b) {
    return a.status == b.status && a.reason == b.reason && std::memcmp(&a.fitness, &b.fitness, sizeof(double)) == 0 &&
           std::memcmp(&a.distance, &b.distance, sizeof(double)) == 0 &&
           std::memcmp(&a.px_per_frame, &b.px_per_frame, sizeof(double)) == 0;
  };
  const std::vector<Evaluation> batch = SingleRollout().estimate(walk_problem_of(config), ptrs);
  REQUIRE(batch.size() == creatures.size());
  int ok = 0;
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    INFO("creature " << i);
    CHECK(same(batch[i], evaluate_creature(creatures[i], config)));
    ok += batch[i].ok() ? 1 : 0;
  }
  CHECK(!batch[4].ok());
  CHECK(ok >= 17);
  for (int threads : {1, 2, 3}) {
    for (std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{4}, std::size_t{7}}) {
      const std::vector<Evaluation> again = ThreadEvaluator(threads, size).evaluate(ptrs, walk_problem_of(config), SingleRollout());
      for (std::size_t i = 0; i < creatures.size(); ++i) CHECK(same(again[i], batch[i]));
    }
  }
}

TEST_CASE("a saved generation declares ISO-8859-1 and holds any reason text as written", "[evolve]") {
  // A reason with a latin-1 letter, a character beyond latin-1, markup and a line
  // break: each must read back as written (an untranscoded UTF-8 byte pair would
  // read back as two latin-1 letters, a raw line break in an attribute as a space).
  const std::string reason = "caf\xC3\xA9 \xE2\x86\x92 <bar & \"end\">\nnext line";
  Generation g;
  g.index = 1;
  Individual ind;
  ind.id = "g1-0";
  ind.creature = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  ind.evaluation.status = EvaluationStatus::Invalid;
  ind.evaluation.reason = reason;
  ind.evaluated = true;
  g.individuals.push_back(ind);
  const std::string xml = generation_to_xml(g);
  CHECK(xml.find("encoding=\"ISO-8859-1\"") != std::string::npos);
  CHECK(xml.find("caf\xE9 &#8594; &lt;bar &amp; &quot;end&quot;&gt;&#10;next line") != std::string::npos);
  const Generation back = generation_from_xml(xml, "mem");
  REQUIRE(back.individuals.size() == 1);
  CHECK(back.individuals[0].evaluation.reason == reason);
}

TEST_CASE("creatures that were not scored: no infinity in any file, and they read back unscored", "[evolve]") {
  const soda::ModelDef walker = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  Generation g;
  g.index = 3;
  const EvaluationStatus statuses[] = {EvaluationStatus::Invalid, EvaluationStatus::Diverged};
  for (int i = 0; i < 2; ++i) {
    Individual ind;
    ind.id = "g3-" + std::to_string(i);
    ind.creature = walker;
    ind.evaluation.status = statuses[i];
    ind.evaluation.reason = "made up for the test";
    ind.evaluated = true;
    g.individuals.push_back(ind);
  }
  const std::string xml = generation_to_xml(g);
  CHECK(xml.find("inf") == std::string::npos);
  const Generation back = generation_from_xml(xml, "mem");
  REQUIRE(back.individuals.size() == 2);
  for (int i = 0; i < 2; ++i) {
    CHECK(back.individuals[i].evaluation.status == statuses[i]);
    CHECK(back.individuals[i].evaluation.fitness == kWorstFitness); // below every scored creature, in memory
  }
  CHECK(generation_to_xml(back) == xml);

  // A scored creature must carry its fitness; an unscored one must not.
  std::string missing = xml;
  missing.replace(missing.find("status=\"invalid\""), 16, "status=\"ok\"");
  CHECK_THROWS_WITH(generation_from_xml(missing, "mem"), Catch::Contains("expected a number for a scored creature"));

  // A generation without a single scored creature: empty statistics, no infinity.
  const fs::path dir = fresh_dir("unscored");
  RunStore store = RunStore::create(dir, small_config(), false, "test");
  const GenerationStats stats = summarize(g, 2);
  store.record_generation(g, stats, 1.0, 1.0, 2, true, std::nullopt);
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    INFO(e.path());
    const std::string text = evolve_file_text(e.path());
    CHECK(text.find("inf") == std::string::npos);
  }
  CHECK(evolve_file_text(dir / "generations.csv").find("\n3,2,,,,,1,1,,,,,\n") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("a seed model that cannot be evolved is a config error, before any run folder exists", "[evolve][cli]") {
  const fs::path dir = fresh_dir("bad_seed");
  fs::create_directories(dir);
  const fs::path config = dir / "bad_seed.json";
  std::ofstream(config) << R"({"name": "bad_seed", "generations": 2,
    "population": {"size": 4, "seed_models": [")" << (test::models_dir() / "dainty_walker.xml").string() << R"("],
                   "random_fraction": 0, "random": {"masses_min": 3, "masses_max": 4}},
    "limits": {"max_masses": 4}, "fitness": {"frames": 50, "settle_frames": 5}})";
  const fs::path run = dir / "run";
  const test::ShellResult r =
      test::run_shell(std::string(SODAEVO_BINARY) + " evolve " + config.string() + " --out " + run.string());
  INFO(r.output);
  CHECK(r.exit_code != 0);
  CHECK(r.output.find(config.string()) != std::string::npos);
  CHECK(r.output.find("/population/seed_models/0") != std::string::npos);
  CHECK(r.output.find("10 masses") != std::string::npos);
  CHECK(!fs::exists(run));
  fs::remove_all(dir);
}

TEST_CASE("a run folder without its manifest (killed right after its config) gets one on resume", "[evolve]") {
  const fs::path dir = fresh_dir("no_manifest");
  { RunStore::create(dir, small_config(), false, "test"); }
  fs::remove(dir / "manifest.json");
  RunStore::open(dir);
  REQUIRE(fs::exists(dir / "manifest.json"));
  const std::string manifest = evolve_file_text(dir / "manifest.json");
  CHECK(manifest.find("killed before its manifest was written") != std::string::npos);
  CHECK(manifest.find("\"seed\": 42") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("the single-rollout estimator: the rollout's score is the fitness, refused creatures name why", "[evolve]") {
  const RunConfig config = small_config();
  const WalkProblem problem = walk_problem_of(config);
  const soda::ModelDef walker = creature_from_seed(soda::read_model_file(test::models_dir() / "dainty_walker.xml").def, config);
  soda::ModelDef unlinked = walker;
  unlinked.links.clear();
  const std::vector<Evaluation> e = SingleRollout().estimate(problem, {&walker, &unlinked});
  REQUIRE(e[0].ok());
  // The one rollout, scored as the reference step scores it (settle, then the
  // centroid's displacement).
  const soda::ModelDef prepared = problem.prepare(walker);
  const soda::Model model = soda::build_model(prepared);
  soda::State state = soda::make_state(model);
  soda::run(model, state, config.fitness.settle_frames);
  const double start_x = soda::mass_centroid(model, state).x;
  soda::run(model, state, config.fitness.frames);
  CHECK(e[0].fitness == soda::mass_centroid(model, state).x - start_x);
  CHECK(e[0].estimate == Estimate{1, e[0].fitness, 0.0, e[0].fitness});
  CHECK(e[1].status == EvaluationStatus::Invalid);
  CHECK(e[1].reason == "creature has no links");
  CHECK(e[1].estimate.rollouts == 0);
  CHECK_THROWS_WITH(problem.prepare(unlinked), "creature has no links");
}
