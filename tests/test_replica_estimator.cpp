// The replica estimator (issue: fitness as a measured estimate): seeds, the
// statistic, replicas checked against the reference step run by hand, adaptive
// resampling, the estimate saved with a generation, and the check on fresh
// replicas.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <set>

#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/algorithms/rng.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/algorithms/variation.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;

namespace {

RunConfig walker_config(int replicas, int replicas_max) {
  RunConfig c = test::walker_run_config("replicas", 7, 8, 2, 300, 40);
  c.fitness.replicas = replicas;
  c.fitness.replicas_max = replicas_max;
  return c;
}

soda::ModelDef estimator_dainty() { return soda::read_model_file(test::models_dir() / "dainty_walker.xml").def; }

/// The distance of one replica run by hand with the reference step (soda::run),
/// independent of the problem's batched rollouts.
double reference_distance(const soda::ModelDef& prepared, const soda::SineJitter& jitter, const FitnessConfig& f) {
  const soda::Model model = soda::build_model(prepared);
  soda::State state = soda::make_state(model);
  state.jitter = jitter;
  soda::run(model, state, f.settle_frames);
  const double start = soda::mass_centroid(model, state).x;
  soda::run(model, state, f.frames);
  return soda::mass_centroid(model, state).x - start;
}

/// Generation 0 of `count` Dainty Walkers, creature i changed by vary(creature, i).
Generation generation_of(int count, const std::function<void(soda::ModelDef&, int)>& vary) {
  Generation g;
  for (int i = 0; i < count; ++i) {
    Individual ind;
    ind.id = "g0-" + std::to_string(i);
    ind.creature = estimator_dainty();
    vary(ind.creature, i);
    g.individuals.push_back(ind);
  }
  return g;
}

} // namespace

TEST_CASE("replica seeds: replica 0 exact, the others nonzero, distinct, and apart from the check's",
          "[replicas]") {
  const std::uint64_t key = creature_key(estimator_dainty());
  CHECK(replica_seed(1, ReplicaPurpose::Selection, key, 0) == 0);
  std::set<std::uint64_t> seen;
  for (int r = 1; r < 200; ++r) {
    const std::uint64_t s = replica_seed(1, ReplicaPurpose::Selection, key, r);
    CHECK(s != 0);
    seen.insert(s);
    seen.insert(replica_seed(1, ReplicaPurpose::Check, key, r));
  }
  CHECK(seen.size() == 2 * 199);
  CHECK(replica_seed(1, ReplicaPurpose::Check, key, 0) != 0);
  CHECK(replica_seed(2, ReplicaPurpose::Selection, key, 5) != replica_seed(1, ReplicaPurpose::Selection, key, 5));
  // The key is the genome: a renamed copy has the same replicas.
  soda::ModelDef renamed = estimator_dainty();
  renamed.name = "another name";
  CHECK(creature_key(renamed) == key);
  renamed.nodes[0].x += 1.0;
  CHECK(creature_key(renamed) != key);
}

TEST_CASE("the replica statistic: mean, median and the lower confidence bound", "[replicas]") {
  const std::vector<double> scores{10.0, 1.0, 3.0, 2.0, 4.0};
  CHECK(replica_statistic(scores, EstimateStatistic::Mean) == 4.0);
  CHECK(replica_statistic(scores, EstimateStatistic::Median) == 3.0);
  // mean - t(0.975, 4) sd / sqrt(5), t = 2.776445 (table), sd^2 = 50 / 4.
  CHECK(replica_statistic(scores, EstimateStatistic::LowerBound) ==
        Approx(4.0 - 2.776445 * std::sqrt(12.5) / std::sqrt(5.0)).epsilon(1e-6));
  CHECK(replica_statistic({7.0}, EstimateStatistic::LowerBound) == 7.0);
}

TEST_CASE("replicas: each replica is the reference step with its jitter, replica 0 is the exact run",
          "[replicas]") {
  const RunConfig config = walker_config(6, 12);
  const WalkProblem problem = walk_problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  const soda::ModelDef creature = estimator_dainty();
  const Evaluation e = estimator.estimate(problem, {&creature}).front();
  REQUIRE(e.ok());
  REQUIRE(e.estimate.rollouts == 6);

  const soda::ModelDef prepared = problem.prepare(creature);
  const std::uint64_t key = creature_key(creature);
  std::vector<double> by_hand;
  for (int r = 0; r < 6; ++r) {
    const soda::SineJitter jitter{replica_seed(config.seed, ReplicaPurpose::Selection, key, r), config.fitness.jitter};
    by_hand.push_back(reference_distance(prepared, jitter, config.fitness));
  }
  // Walking right: fitness = distance.
  CHECK(test::same_bits(e.distance, by_hand[0]));
  const SampleSummary s = summarize_sample(by_hand);
  CHECK(test::same_bits(e.estimate.mean, s.mean));
  CHECK(test::same_bits(e.estimate.median, s.median));
  CHECK(test::same_bits(e.fitness, s.mean));
  // Over 340 frames the jittered replicas leave the exact run.
  CHECK(s.sd > 0.0);

  // One replica is today's single exact rollout.
  const Evaluation single = ReplicaEstimator(replica_plan(walker_config(1, 1))).estimate(problem, {&creature}).front();
  CHECK(test::same_bits(single.fitness, by_hand[0]));
  CHECK(single.estimate.rollouts == 1);
}

TEST_CASE("adaptive resampling: survivors gather replicas up to the cap, whatever the thread count",
          "[replicas]") {
  const RunConfig config = walker_config(2, 5);
  const WalkProblem problem = walk_problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  Generation g = generation_of(3, [](soda::ModelDef& c, int i) { c.nodes[0].x += i; });
  ThreadEvaluator one(1), two(2);
  CHECK(evaluate_generation(one, g, problem, estimator) == 3);
  for (const Individual& ind : g.individuals) CHECK(ind.evaluation.estimate.rollouts == 2);
  Generation copy = g;
  // Every creature survives: 2 -> 4 -> 5 (the cap) -> kept.
  CHECK(evaluate_generation(one, g, problem, estimator) == 3);
  CHECK(evaluate_generation(two, copy, problem, estimator) == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(g.individuals[i].evaluation.estimate.rollouts == 4);
    CHECK(test::same_bits(g.individuals[i].evaluation.fitness, copy.individuals[i].evaluation.fitness));
    // The resampled estimate is the estimate on 4 replicas from scratch.
    const Evaluation fresh =
        estimator.with_rollouts(4)->estimate(problem, {&g.individuals[i].creature}).front();
    CHECK(test::same_bits(fresh.fitness, g.individuals[i].evaluation.fitness));
  }
  CHECK(evaluate_generation(one, g, problem, estimator) == 3);
  for (const Individual& ind : g.individuals) CHECK(ind.evaluation.estimate.rollouts == 5);
  CHECK(evaluate_generation(one, g, problem, estimator) == 0);
}

TEST_CASE("confirmation: the best end estimated on replicas_max, ranked again until they all are",
          "[replicas]") {
  RunConfig config = walker_config(2, 8);
  config.fitness.frames = 2000; // past the mutants' predictability horizon: replicas differ
  const WalkProblem problem = walk_problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  // Mutants of the Dainty Walker: a population whose best are partly lucky draws.
  Generation g = generation_of(12, [&](soda::ModelDef& c, int i) {
    Rng rng = Rng::stream(11, 0, static_cast<std::uint64_t>(i), 9);
    mutate(c, config, rng);
  });
  ThreadEvaluator one(1), two(2);
  evaluate_generation(one, g, problem, estimator);
  Generation copy = g;
  const int count = 3;
  const long long done = confirm_best(one, g, problem, estimator, count);
  CHECK(confirm_best(two, copy, problem, estimator, count) == done);
  // Ranked by hand: the best `count` valid ones by fitness must all be on 8.
  std::vector<const Individual*> valid;
  for (const Individual& ind : g.individuals) {
    if (ind.evaluation.ok()) valid.push_back(&ind);
  }
  REQUIRE(valid.size() > static_cast<std::size_t>(count));
  std::stable_sort(valid.begin(), valid.end(), [](const Individual* a, const Individual* b) {
    return a->evaluation.fitness > b->evaluation.fitness;
  });
  for (int k = 0; k < count; ++k) CHECK(valid[static_cast<std::size_t>(k)]->evaluation.estimate.rollouts == 8);
  long long on_max = 0;
  for (std::size_t i = 0; i < g.individuals.size(); ++i) {
    const Evaluation& e = g.individuals[i].evaluation;
    CHECK(test::same_bits(e.fitness, copy.individuals[i].evaluation.fitness));
    if (!e.ok()) continue;
    CHECK((e.estimate.rollouts == 2 || e.estimate.rollouts == 8));
    if (e.estimate.rollouts != 8) continue;
    ++on_max;
    // A confirmed estimate is the estimate on 8 replicas from scratch.
    const Evaluation fresh = estimator.with_rollouts(8)->estimate(problem, {&g.individuals[i].creature}).front();
    CHECK(test::same_bits(fresh.fitness, e.fitness));
  }
  CHECK(on_max == done);
  // Nothing left to confirm: a second call does nothing.
  CHECK(confirm_best(one, g, problem, estimator, count) == 0);
}

namespace {

/// An estimator with made-up scores: creature "A" scores 100 on its first
/// replicas and 10 once confirmed (a lucky draw), and so on (see the test).
class ScriptedEstimator final : public Estimator {
 public:
  explicit ScriptedEstimator(int rollouts = 2) : rollouts_(rollouts) {}
  [[nodiscard]] std::string kind() const override { return "scripted"; }
  [[nodiscard]] std::vector<Evaluation> estimate(const Problem&,
                                                 const std::vector<const soda::ModelDef*>& creatures) const override {
    std::vector<Evaluation> out;
    for (const soda::ModelDef* c : creatures) {
      Evaluation e;
      if (c->name != "E") {
        const std::map<std::string, std::pair<double, double>> scores = {
            {"A", {100, 10}}, {"B", {90, 85}}, {"C", {80, 82}}, {"D", {70, 70}}};
        const auto [first, confirmed] = scores.at(c->name);
        e.status = EvaluationStatus::Ok;
        e.fitness = rollouts_ >= 8 ? confirmed : first;
        e.estimate = {rollouts_, e.fitness, 1.0, e.fitness};
      }
      out.push_back(e);
    }
    return out;
  }
  [[nodiscard]] int confirm_to(const Evaluation& kept) const override {
    return kept.ok() && kept.estimate.rollouts < 8 ? 8 : 0;
  }
  [[nodiscard]] std::unique_ptr<Estimator> with_rollouts(int rollouts) const override {
    return std::make_unique<ScriptedEstimator>(rollouts);
  }
  void write(WireWriter&) const override {}

 private:
  int rollouts_;
};

} // namespace

TEST_CASE("confirmation ranks again: a lucky best falls back and the next is confirmed", "[replicas]") {
  const WalkProblem problem = walk_problem_of(walker_config(2, 8));
  const ScriptedEstimator estimator;
  Generation g;
  for (const char* name : {"E", "D", "C", "B", "A"}) {
    Individual ind;
    ind.id = name;
    ind.creature = estimator_dainty();
    ind.creature.name = name;
    g.individuals.push_back(ind);
  }
  ThreadEvaluator one(1);
  evaluate_generation(one, g, problem, estimator);
  // Best 2 at first: A (100) and B (90). Confirmed, A falls to 10 and B to 85; then
  // C (80) is among the best 2 and is confirmed (82); then B and C are both done.
  CHECK(confirm_best(one, g, problem, estimator, 2) == 3);
  const auto find = [&](const std::string& id) -> const Evaluation& {
    for (const Individual& ind : g.individuals) {
      if (ind.id == id) return ind.evaluation;
    }
    throw std::logic_error("no " + id);
  };
  CHECK(find("A").fitness == 10);
  CHECK(find("B").fitness == 85);
  CHECK(find("C").fitness == 82);
  CHECK(find("C").estimate.rollouts == 8);
  CHECK(find("D").estimate.rollouts == 2); // never among the best 2
  CHECK(!find("E").ok());
  CHECK(confirm_best(one, g, problem, estimator, 0) == 0);
}

TEST_CASE("a saved generation keeps each creature's estimate", "[replicas]") {
  const RunConfig config = walker_config(3, 6);
  const WalkProblem problem = walk_problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  Generation g;
  Individual ind;
  ind.id = "g0-0";
  ind.creature = estimator_dainty();
  g.individuals.push_back(ind);
  ThreadEvaluator one(1);
  evaluate_generation(one, g, problem, estimator);
  const Generation back = generation_from_xml(generation_to_xml(g), "test");
  CHECK(back.individuals[0].evaluation.estimate == g.individuals[0].evaluation.estimate);
  CHECK(test::same_bits(back.individuals[0].evaluation.fitness, g.individuals[0].evaluation.fitness));
  // A bad count is an error naming the attribute.
  std::string text = generation_to_xml(g);
  text.replace(text.find("replicas=\"3\""), 12, "replicas=\"0\"");
  CHECK_THROWS_WITH(generation_from_xml(text, "gen.xml"), Catch::Contains("replicas") && Catch::Contains("got '0'"));
}

TEST_CASE("the check on fresh replicas: exact distance, the fresh ensemble, the winner's curse", "[replicas]") {
  const RunConfig config = walker_config(4, 8);
  const WalkProblem problem = walk_problem_of(config);
  const ReplicaEstimator estimator(replica_plan(config));
  Individual ind;
  ind.id = "g3-1";
  ind.creature = estimator_dainty();
  ind.evaluation = estimator.estimate(problem, {&ind.creature}).front();
  const ReplicaCheck c = check_on_fresh_replicas(problem, ind, replica_plan(config), 5);
  REQUIRE(c.ok);
  const soda::ModelDef prepared = problem.prepare(ind.creature);
  CHECK(test::same_bits(c.exact_distance, reference_distance(prepared, {}, config.fitness)));
  std::vector<double> by_hand;
  const std::uint64_t key = creature_key(ind.creature);
  for (int r = 0; r < 5; ++r) {
    by_hand.push_back(reference_distance(
        prepared, {replica_seed(config.seed, ReplicaPurpose::Check, key, r), config.fitness.jitter}, config.fitness));
  }
  const SampleSummary s = summarize_sample(by_hand);
  CHECK(c.check.n == 5);
  CHECK(test::same_bits(c.check.mean, s.mean));
  CHECK(c.winners_curse == Approx(ind.evaluation.estimate.mean - s.mean));
  const nlohmann::json j = champion_json(c, "rank01_g3-1.xml", config.fitness.settle_frames, config.fitness.frames);
  CHECK(j["id"] == "g3-1");
  CHECK(j["settle_frames"] == 40);
  CHECK(j["selection"]["n"] == 4);
  CHECK(j["check"]["interval95"].size() == 2);
  CHECK(j["check"]["interval95"][0].get<double>() <= j["check"]["interval95"][1].get<double>());
  CHECK(j["check"]["interval95"][0].get<double>() == c.check.interval95_low);
}
