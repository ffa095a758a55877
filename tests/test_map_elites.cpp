// MAP-Elites: descriptors, the grid archive's cells, insertion and resampling
// rules, QD metrics, and the /map_elites config.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "bench/qd_bench.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/algorithms/grid_archive.hpp"
#include "evolve/config/map_elites_config.hpp"
#include "evolve/runs/map_elites_run.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;

namespace {

double at(const Behaviour& b, Descriptor d) { return b[static_cast<std::size_t>(d)]; }

RunningEstimate estimate(long long n, double mean) {
  RunningEstimate e;
  e.n = n;
  e.mean = mean;
  return e;
}

} // namespace

TEST_CASE("descriptor meter: hand-computed extents, centroid height and floor contact", "[map-elites]") {
  soda::Model model;
  model.mass_count = 3;
  model.point_count = 3;
  model.link_muscle = {1, 0, 0};
  model.link_a = {0, 1, 0};
  model.link_b = {1, 2, 2};
  DescriptorMeter meter(model);
  soda::State s;
  s.x = {0, 4, 10};
  s.y = {0.5, 3, 1}; // min y 0.5: touching (within 1 px)
  meter.observe(s);
  s.x = {0, 2, 6};
  s.y = {2, 5, 8}; // in the air
  meter.observe(s);
  const Behaviour b = meter.behaviour();
  CHECK(at(b, Descriptor::MassCount) == 3);
  CHECK(at(b, Descriptor::MuscleShare) == Approx(1.0 / 3.0));
  CHECK(at(b, Descriptor::Width) == Approx((10.0 + 6.0) / 2));
  CHECK(at(b, Descriptor::Height) == Approx((2.5 + 6.0) / 2));
  CHECK(at(b, Descriptor::CentroidHeight) == Approx((4.5 / 3 + 15.0 / 3) / 2));
  CHECK(at(b, Descriptor::FloorContact) == 0.5);
  CHECK(meter.samples() == 2);
}

TEST_CASE("walk problem with descriptors: the fitness bits of the plain rollout, descriptors sampled on the reference run",
          "[map-elites]") {
  RunConfig config = test::walker_run_config("d", 1, 4, 1, 300, 40);
  const soda::ModelDef walker = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  const long long every = 7; // 300 = 42 * 7 + 6: the last sample comes after a shorter chunk
  const WalkProblem plain_problem(config.fitness, config.world, config.limits);
  const WalkProblem problem(config.fitness, config.world, config.limits, every);
  const soda::ModelDef prepared = problem.prepare(walker);
  const soda::SineJitter jitter{replica_seed(1, ReplicaPurpose::Selection, 99, 1), 0.05};
  const std::vector<Evaluation> described = problem.rollouts({&prepared, Rollout(&prepared, jitter)});
  const std::vector<Evaluation> plain = plain_problem.rollouts({&prepared, Rollout(&prepared, jitter)});
  REQUIRE(described.size() == 2);
  REQUIRE(described[0].ok());
  REQUIRE(described[1].ok());
  CHECK(plain[0].descriptors.empty());
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(test::same_bits(described[k].fitness, plain[k].fitness));
    CHECK(test::same_bits(described[k].distance, plain[k].distance));
    REQUIRE(described[k].descriptors.size() == kDescriptorCount);
  }

  // The reference stepper, one frame at a time, sampled at scored frames 7, 14, ..., 294, 300.
  const soda::Model model = soda::build_model(prepared);
  for (std::size_t k = 0; k < 2; ++k) {
    soda::State state = soda::make_state(model);
    state.jitter = k == 0 ? soda::SineJitter{} : jitter;
    soda::run(model, state, config.fitness.settle_frames);
    DescriptorMeter meter(model);
    for (long long f = 1; f <= config.fitness.frames; ++f) {
      soda::step(model, state);
      if (f % every == 0 || f == config.fitness.frames) meter.observe(state);
    }
    CHECK(meter.samples() == 43);
    for (std::size_t d = 0; d < kDescriptorCount; ++d) {
      INFO("replica " << k << " " << descriptor_names()[d]);
      CHECK(test::same_bits(described[k].descriptors[d], meter.behaviour()[d]));
    }
  }
  // The walker keeps its masses, stays on its feet and is wider than tall.
  const std::vector<double>& b = described[0].descriptors;
  CHECK(b[static_cast<std::size_t>(Descriptor::MassCount)] == static_cast<double>(walker.nodes.size()));
  CHECK(b[static_cast<std::size_t>(Descriptor::FloorContact)] == 1.0);
  CHECK(b[static_cast<std::size_t>(Descriptor::Width)] > b[static_cast<std::size_t>(Descriptor::Height)]);

  // The watched rollout (energy check: one frame at a time) samples the same frames.
  FitnessConfig watched = config.fitness;
  watched.divergence = DivergenceCheck::Energy;
  const Evaluation w = WalkProblem(watched, config.world, config.limits, every).rollouts({&prepared}).front();
  REQUIRE(w.ok());
  CHECK(test::same_bits(w.distance, described[0].distance));
  REQUIRE(w.descriptors.size() == kDescriptorCount);
  for (std::size_t d = 0; d < kDescriptorCount; ++d) CHECK(test::same_bits(w.descriptors[d], b[d]));
}

TEST_CASE("replica estimator: descriptors are the replicas' means, a replica range extends the first replicas",
          "[map-elites]") {
  RunConfig config = test::walker_run_config("d", 3, 4, 1, 300, 40);
  const soda::ModelDef walker = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  const WalkProblem problem(config.fitness, config.world, config.limits, 10);
  ReplicaPlan plan;
  plan.replicas = 4;
  plan.replicas_max = 8;
  plan.jitter = 0.05; // replicas that part early
  plan.run_seed = 3;
  const ReplicaEstimator estimator(plan);
  const Evaluation all = estimator.estimate(problem, {&walker}).front();
  REQUIRE(all.ok());
  REQUIRE(all.estimate.rollouts == 4);

  // The same replicas one by one, as rollouts of the prepared walker with their seeds.
  const soda::ModelDef prepared = problem.prepare(walker);
  const std::uint64_t key = creature_key(walker);
  std::vector<Evaluation> runs;
  for (int r = 0; r < 4; ++r) {
    runs.push_back(
        problem.rollouts({Rollout(&prepared, {replica_seed(3, ReplicaPurpose::Selection, key, r), 0.05})}).front());
    REQUIRE(runs.back().ok());
  }
  CHECK(test::same_bits(all.distance, runs[0].distance)); // replica 0, the exact run
  CHECK((runs[1].fitness != runs[0].fitness || runs[2].fitness != runs[0].fitness)); // the replicas do differ
  for (std::size_t d = 0; d < kDescriptorCount; ++d) {
    double sum = 0.0;
    for (const Evaluation& e : runs) sum += e.descriptors[d];
    CHECK(test::same_bits(all.descriptors[d], sum / 4.0));
  }
  CHECK(all.estimate.mean == Approx((runs[0].fitness + runs[1].fitness + runs[2].fitness + runs[3].fitness) / 4));

  // Replicas [2, 4) alone: replicas 2 and 3 of the estimate above.
  const Evaluation later = estimator.on_replicas(2, 2).estimate(problem, {&walker}).front();
  REQUIRE(later.ok());
  CHECK(later.estimate.rollouts == 2);
  CHECK(test::same_bits(later.distance, runs[2].distance));
  CHECK(later.estimate.mean == Approx((runs[2].fitness + runs[3].fitness) / 2));
  // Merged with replicas [0, 2), the archive's running estimate is the estimate of [0, 4).
  const Evaluation earlier = estimator.on_replicas(0, 2).estimate(problem, {&walker}).front();
  RunningEstimate merged;
  merged.merge(earlier.estimate.rollouts, earlier.estimate.mean, earlier.estimate.sd);
  CHECK(test::same_bits(merged.mean, earlier.estimate.mean)); // the first batch exactly
  merged.merge(later.estimate.rollouts, later.estimate.mean, later.estimate.sd);
  CHECK(merged.n == 4);
  CHECK(merged.mean == Approx(all.estimate.mean).epsilon(1e-12));
  CHECK(merged.sd() == Approx(all.estimate.sd).epsilon(1e-9));
}

TEST_CASE("grid archive: cells are row-major, values outside a range clamp to the edge bins", "[map-elites]") {
  const GridArchive archive({{Descriptor::Width, 4, 0.0, 100.0},
                             {Descriptor::Height, 5, 10.0, 60.0},
                             {Descriptor::MassCount, 3, 2.5, 5.5}});
  CHECK(archive.cell_count() == 60);
  CHECK(archive.bin_of(0, 0.0) == 0);
  CHECK(archive.bin_of(0, 24.999) == 0);
  CHECK(archive.bin_of(0, 25.0) == 1);
  CHECK(archive.bin_of(0, 99.999) == 3);
  CHECK(archive.bin_of(0, 100.0) == 3);  // the top edge belongs to the last bin
  CHECK(archive.bin_of(0, 1e9) == 3);
  CHECK(archive.bin_of(0, -5.0) == 0);
  CHECK(archive.bin_of(0, NAN) == 0);
  CHECK(archive.bin_of(2, 4.0) == 1);    // 4 masses: the middle bin of 3, 4, 5
  // width 60 -> bin 2, height 35 -> bin 2, masses 5 -> bin 2: (2 * 5 + 2) * 3 + 2 = 38
  CHECK(archive.cell_of(std::vector<double>{60.0, 35.0, 5.0}) == 38);
  CHECK(archive.coordinates(38) == std::vector<int>{2, 2, 2});
  CHECK(archive.coordinates(59) == std::vector<int>{3, 4, 2});
  Behaviour b{};
  b[static_cast<std::size_t>(Descriptor::Width)] = 60.0;
  b[static_cast<std::size_t>(Descriptor::Height)] = 35.0;
  b[static_cast<std::size_t>(Descriptor::MassCount)] = 5.0;
  CHECK(archive.cell_of(b) == 38);
}

TEST_CASE("insertion rule: an empty cell takes the challenger, a lead at equal counts is confirmed first",
          "[map-elites]") {
  const ResamplePlan plan{8, 4};
  CHECK(judge(nullptr, estimate(1, -50.0), plan, false).verdict == Verdict::Enter);
  const RunningEstimate elite = estimate(4, 100.0);
  // Ahead on equal counts: both get `step` more replicas before the verdict...
  const Judgement j = judge(&elite, estimate(4, 100.5), plan, false);
  CHECK(j.verdict == Verdict::SampleBoth);
  CHECK(j.replicas == 4);
  // ... then the higher mean wins.
  CHECK(judge(&elite, estimate(4, 100.5), plan, true).verdict == Verdict::Replace);
  CHECK(judge(&elite, estimate(4, 100.0), plan, false).verdict == Verdict::Reject); // a tie keeps the elite
  CHECK(judge(&elite, estimate(4, 99.0), plan, false).verdict == Verdict::Reject);
  // A confirmation stops at the cap.
  const RunningEstimate six = estimate(6, 100.0);
  CHECK(judge(&six, estimate(6, 101.0), plan, false).replicas == 2);
  // Plain MAP-Elites: one replica each, cap 1.
  const RunningEstimate one = estimate(1, 10.0);
  CHECK(judge(&one, estimate(1, 11.0), {1, 1}, false).verdict == Verdict::Replace);
  CHECK(judge(&one, estimate(1, 9.0), {1, 1}, false).verdict == Verdict::Reject);
}

TEST_CASE("resampling rule: counts are made comparable before a challenger replaces an elite", "[map-elites]") {
  const RunningEstimate elite = estimate(16, 100.0);
  // A challenger on fewer replicas that looks better is sampled up to the elite's count...
  Judgement j = judge(&elite, estimate(4, 120.0), {32, 4}, false);
  CHECK(j.verdict == Verdict::SampleChallenger);
  CHECK(j.replicas == 12);
  // ... up to the cap only.
  j = judge(&elite, estimate(4, 120.0), {8, 4}, false);
  CHECK(j.verdict == Verdict::SampleChallenger);
  CHECK(j.replicas == 4);
  const RunningEstimate capped = estimate(8, 100.0);
  // A challenger that does not look better on what it has is rejected at once.
  CHECK(judge(&elite, estimate(4, 100.0), {32, 4}, false).verdict == Verdict::Reject);
  CHECK(judge(&elite, estimate(4, 80.0), {32, 4}, false).verdict == Verdict::Reject);
  // An elite on fewer replicas than the challenger gathers more first, whatever the means.
  const RunningEstimate young = estimate(2, 100.0);
  j = judge(&young, estimate(8, 50.0), {32, 4}, false);
  CHECK(j.verdict == Verdict::SampleElite);
  CHECK(j.replicas == 6);
  j = judge(&young, estimate(8, 150.0), {4, 4}, false);
  CHECK(j.verdict == Verdict::SampleElite);
  CHECK(j.replicas == 2);
  // Both at the cap: comparable, no confirmation left to ask for.
  CHECK(judge(&capped, estimate(8, 101.0), {8, 4}, false).verdict == Verdict::Replace);
  CHECK(judge(&capped, estimate(12, 101.0), {8, 4}, false).verdict == Verdict::Replace);
}

namespace {

/// An Ok estimate over `n` replicas with mean `mean` (sd 0) at descriptors
/// placing it by width and mass count.
Evaluation estimate_of(int n, double mean, double width = 50.0, double masses = 4.0) {
  Evaluation e;
  e.status = EvaluationStatus::Ok;
  e.fitness = mean;
  e.estimate = {n, mean, 0.0, mean};
  e.descriptors.assign(kDescriptorCount, 0.0);
  e.descriptors[static_cast<std::size_t>(Descriptor::Width)] = width;
  e.descriptors[static_cast<std::size_t>(Descriptor::MassCount)] = masses;
  return e;
}

Challenger challenger(const std::string& id, const Evaluation& first) {
  Challenger c;
  c.individual.id = id;
  c.individual.creature.name = id;
  c.first = first;
  return c;
}

/// A sampler that answers from a script: the next estimate for each creature by
/// name, and logs every request as "name first+count".
struct ScriptedSampler {
  std::map<std::string, std::vector<Evaluation>> answers;
  std::vector<std::vector<std::string>> calls;
  ReplicaSampler sampler() {
    return [this](const std::vector<SampleRequest>& requests) {
      std::vector<Evaluation> out;
      calls.emplace_back();
      for (const SampleRequest& r : requests) {
        std::vector<Evaluation>& next = answers.at(r.creature->name);
        REQUIRE(!next.empty());
        Evaluation e = next.front();
        next.erase(next.begin());
        if (e.ok()) REQUIRE(e.estimate.rollouts == r.count);
        calls.back().push_back(r.creature->name + " " + std::to_string(r.first) + "+" + std::to_string(r.count));
        out.push_back(e);
      }
      return out;
    };
  }
};

} // namespace

TEST_CASE("insertion: a lucky lead is confirmed on more replicas, elites gather them, failures leave",
          "[map-elites]") {
  GridArchive archive({{Descriptor::Width, 4, 0.0, 200.0}, {Descriptor::MassCount, 4, 2.5, 6.5}});
  const ResamplePlan plan{6, 2};
  ScriptedSampler script;
  // E enters an empty cell without further replicas.
  InsertionCounts c = insert_challengers(archive, {challenger("E", estimate_of(2, 100.0))}, 0, plan, script.sampler());
  CHECK(c.entered == 1);
  CHECK(script.calls.empty());
  const std::size_t cell = archive.cell_of(std::vector<double>{50.0, 4.0});
  REQUIRE(archive.elite(cell) != nullptr);

  // L leads 110 to 100 on 2 replicas; confirmed on 2 more each, it is 100 to 100: rejected.
  script.answers["L"] = {estimate_of(2, 90.0)};
  script.answers["E"] = {estimate_of(2, 100.0, 70.0)};
  c = insert_challengers(archive, {challenger("L", estimate_of(2, 110.0))}, 1, plan, script.sampler());
  CHECK(c.rejected == 1);
  CHECK(c.resampled == 2);
  CHECK(c.resampled_rollouts == 4);
  REQUIRE(script.calls.size() == 1);
  CHECK(script.calls[0] == std::vector<std::string>{"L 2+2", "E 2+2"});
  const ArchiveEntry& e = *archive.elite(cell);
  CHECK(e.id == "E");
  CHECK(e.fitness.n == 4); // the elite gathered replicas
  CHECK(e.fitness.mean == 100.0);
  CHECK(e.descriptors[0] == 60.0); // width: the mean of 50 over 2 and 70 over 2 replicas

  // B leads on fewer replicas: sampled up to the elite's 4, still ahead, confirmed
  // with the elite on 2 more (the cap, 6): B takes the cell. O, in another cell,
  // enters at once; W, behind B in the same cell, is judged against B once B has won.
  script.calls.clear();
  script.answers["B"] = {estimate_of(2, 120.0), estimate_of(2, 110.0)};
  script.answers["E"] = {estimate_of(2, 100.0)};
  c = insert_challengers(archive,
                         {challenger("B", estimate_of(2, 130.0)), challenger("O", estimate_of(2, 5.0, 150.0, 6.0)),
                          challenger("W", estimate_of(2, 101.0))},
                         2, plan, script.sampler());
  CHECK(c.entered == 1);
  CHECK(c.replaced == 1);
  CHECK(c.rejected == 1); // W: fewer replicas than B and not ahead of it
  CHECK(script.calls == std::vector<std::vector<std::string>>{{"B 2+2"}, {"B 4+2", "E 4+2"}});
  CHECK(archive.elite(cell)->id == "B");
  CHECK(archive.elite(cell)->fitness.n == 6);
  CHECK(archive.elite(cell)->fitness.mean == Approx((130.0 * 2 + 120.0 * 2 + 110.0 * 2) / 6));

  // An elite that fails on a further replica leaves; its challenger enters.
  script.calls.clear();
  Evaluation diverged;
  diverged.status = EvaluationStatus::Diverged;
  script.answers["B"] = {diverged};
  c = insert_challengers(archive, {challenger("N", estimate_of(8, 1.0))}, 3, {8, 2}, script.sampler());
  CHECK(script.calls == std::vector<std::vector<std::string>>{{"B 6+2"}});
  CHECK(c.evicted == 1);
  CHECK(c.entered == 1);
  CHECK(archive.elite(cell)->id == "N");
}

TEST_CASE("running estimate: mean and sample sd of replicas", "[map-elites]") {
  RunningEstimate e;
  for (double v : {2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0}) e.add(v);
  CHECK(e.n == 8);
  CHECK(e.mean == 5.0);
  CHECK(e.sd() == Approx(std::sqrt(32.0 / 7.0)));
  RunningEstimate one;
  one.add(3.0);
  CHECK(one.sd() == 0.0);
}

TEST_CASE("QD metrics of a hand-built archive", "[map-elites]") {
  GridArchive archive({{Descriptor::Width, 10, 0.0, 100.0}, {Descriptor::Height, 10, 0.0, 100.0}});
  const QdMetrics empty = archive.metrics(0.0);
  CHECK(empty.cells == 100);
  CHECK(empty.filled == 0);
  CHECK(empty.qd_score == 0.0);
  for (auto [cell, fitness] : std::vector<std::pair<std::size_t, double>>{{3, 50.0}, {17, 150.0}, {99, -20.0}}) {
    ArchiveEntry e;
    e.fitness = estimate(1, fitness);
    archive.place(cell, e);
  }
  const QdMetrics m = archive.metrics(0.0);
  CHECK(m.filled == 3);
  CHECK(m.coverage == 0.03);
  CHECK(m.qd_score == 200.0);  // the backward walker counts 0, not -20
  CHECK(m.normalized_qd_score == 2.0);
  CHECK(m.best == 150.0);
  CHECK(m.mean == Approx(60.0));
  const QdMetrics offset = archive.metrics(-100.0);
  CHECK(offset.qd_score == 150.0 + 250.0 + 80.0);
  CHECK(offset.normalized_qd_score == Approx(4.8));
  CHECK_THROWS(archive.place(100, ArchiveEntry{}));
}

namespace {

std::vector<ConfigProblem> problems_of(const std::string& text) {
  MapElitesConfig config;
  std::vector<ConfigProblem> problems;
  read_map_elites(nlohmann::json::parse(text), config, problems);
  return problems;
}

std::string first(const std::vector<ConfigProblem>& p) {
  return p.empty() ? std::string("(none)") : p.front().pointer + ": " + p.front().message;
}

} // namespace

TEST_CASE("/map_elites config: a full grid reads and writes back", "[map-elites]") {
  MapElitesConfig config;
  std::vector<ConfigProblem> problems;
  read_map_elites(nlohmann::json::parse(R"({"descriptors": ["muscle_share", "floor_contact"], "bins": [5, 4],
      "ranges": [[0, 1], [0, 1]], "batch_size": 10, "iterations": 3, "crossover_rate": 0.25,
      "snapshot_every": 0, "sample_every": 3, "qd_offset": -50, "parent_tournament": 4, "check_replicas": 0})"),
                  config, problems);
  INFO(first(problems));
  REQUIRE(problems.empty());
  REQUIRE(config.axes.size() == 2);
  CHECK(config.axes[0] == GridAxis{Descriptor::MuscleShare, 5, 0.0, 1.0});
  CHECK(config.axes[1] == GridAxis{Descriptor::FloorContact, 4, 0.0, 1.0});
  CHECK(config.batch_size == 10);
  CHECK(config.qd_offset == -50.0);
  CHECK(config.parent_tournament == 4);
  CHECK(config.check_replicas == 0);
  MapElitesConfig back;
  read_map_elites(to_json(config), back, problems);
  CHECK(problems.empty());
  CHECK(back == config);
  // The default grid: 3 axes, 1,000 to 2,000 cells.
  const MapElitesConfig defaults;
  std::size_t cells = 1;
  for (const GridAxis& a : defaults.axes) cells *= static_cast<std::size_t>(a.bins);
  CHECK(defaults.axes.size() == 3);
  CHECK(cells >= 1000);
  CHECK(cells <= 2000);
}

TEST_CASE("/map_elites config: bad input names the pointer, what was expected and what was found", "[map-elites]") {
  const std::string grid = R"("bins": [4, 4], "ranges": [[0, 1], [0, 1]])";
  auto p = problems_of(R"({"descriptors": ["width", "wingspan"], )" + grid + "}");
  CHECK(first(p) == "/map_elites/descriptors/1: expected one of mass_count, muscle_share, width, height, "
                    "centroid_height, floor_contact, got \"wingspan\"");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 0], "ranges": [[0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins/1: expected an integer in [1, 100000], got 0");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4], "ranges": [[0, 1], [5, 5]]})");
  CHECK(first(p) == "/map_elites/ranges/1: expected lo < hi (a range that is neither empty nor inverted), got [5,5]");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4], "ranges": [[3, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/ranges/0: expected lo < hi (a range that is neither empty nor inverted), got [3,1]");
  p = problems_of(R"({"descriptors": ["width", "height", "mass_count"], "bins": [100, 100, 11],
                      "ranges": [[0, 1], [0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins: expected at most 100000 cells (the bins multiplied), got 110000 from "
                    "[100,100,11]");
  p = problems_of(R"({"batch_size": 0})");
  CHECK(first(p) == "/map_elites/batch_size: expected an integer in [1, 100000], got 0");
  p = problems_of(R"({"descriptors": ["width"], "bins": [4], "ranges": [[0, 1]]})");
  CHECK(first(p).rfind("/map_elites/descriptors: expected an array of 2 or 3 descriptor names", 0) == 0);
  p = problems_of(R"({"descriptors": ["width", "width"], )" + grid + "}");
  CHECK(first(p) == "/map_elites/descriptors/1: expected a descriptor not named before, got \"width\"");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4, 4], "ranges": [[0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins: expected an array of 2 integers (one per descriptor), got [4,4,4]");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4]})");
  CHECK(first(p) == "/map_elites/ranges: expected an array (descriptors, bins and ranges are given together), "
                    "got nothing");
  p = problems_of(R"({"elite_recent": -1})");
  CHECK(first(p) == "/map_elites/elite_recent: expected an integer in [0, 1000000], got -1");
  p = problems_of(R"({"batch": 3})");
  CHECK(first(p).rfind("/map_elites/batch: unknown key (expected one of: descriptors, ", 0) == 0);
  p = problems_of(R"([1])");
  CHECK(first(p).rfind("/map_elites: expected an object with keys", 0) == 0);
}

namespace {

/// A small MAP-Elites run: the walker and random creatures, 2 descriptors.
struct SmallRun {
  RunConfig config = test::walker_run_config("me", 7, 12, 1, 300, 40);
  MapElitesConfig me;
  SmallRun() {
    me.axes = {{Descriptor::Width, 6, 0.0, 240.0}, {Descriptor::MassCount, 6, 2.5, 14.5}};
    me.iterations = 4;
    me.batch_size = 10;
    me.crossover_rate = 0.3;
    me.snapshot_every = 2;
    me.sample_every = 5;
    config.save.checkpoint_every = 1;
  }
};

std::filesystem::path run_dir(const std::string& name) {
  return test::fresh_temp_dir("map_elites_" + name);
}

std::string archive_file_text(const std::filesystem::path& p) { return soda::read_whole_file(p); }

} // namespace

TEST_CASE("MAP-Elites run: the same archive on 1, 2 and 8 threads, and resumed after a stop or a crash",
          "[map-elites]") {
  const SmallRun run; // 2 replicas per new creature, up to 4
  const auto one = run_dir("one"), two = run_dir("two"), stopped = run_dir("stopped"), crashed = run_dir("crashed");
  ThreadEvaluator threads1(1), threads2(2);
  const MapElitesOutcome a = run_map_elites(one, run.config, run.me, threads1, {});
  const MapElitesOutcome b = run_map_elites(two, run.config, run.me, threads2, {});
  CHECK(a.stopped_because == StopReason::Completed);
  CHECK(a.last_iteration == 4);
  CHECK(a.evaluations > 12 + 4 * 10); // the children, and the further replicas insertion asked for
  CHECK(a.rollouts >= 2 * a.evaluations); // 2 replicas a creature, 2 more at a time
  CHECK(a.metrics.filled > 3);
  CHECK(b.evaluations == a.evaluations);
  CHECK(archive_file_text(one / "qd.csv") == archive_file_text(two / "qd.csv"));
  CHECK(archive_file_text(one / "archive.json") == archive_file_text(two / "archive.json"));
  const auto eight = run_dir("eight");
  ThreadEvaluator threads8(8, 3); // and batches of 3 creatures
  run_map_elites(eight, run.config, run.me, threads8, {});
  CHECK(archive_file_text(one / "qd.csv") == archive_file_text(eight / "qd.csv"));
  CHECK(archive_file_text(one / "archive.json") == archive_file_text(eight / "archive.json"));

  // Stopped after iteration 2 (as Ctrl-C stops it), then resumed to the end.
  std::atomic<bool> stop{false};
  MapElitesOptions options;
  options.stop_requested = &stop;
  options.on_iteration = [&](const MapElitesProgress& p) {
    if (p.iteration == 2) stop = true;
  };
  const MapElitesOutcome first = run_map_elites(stopped, run.config, run.me, threads2, options);
  CHECK(first.stopped_because == StopReason::Interrupted);
  CHECK(first.last_iteration == 2);
  const MapElitesOutcome rest = run_map_elites(stopped, run.config, run.me, threads2, {});
  CHECK(rest.last_iteration == 4);
  CHECK(archive_file_text(one / "qd.csv") == archive_file_text(stopped / "qd.csv"));
  CHECK(archive_file_text(one / "archive.json") == archive_file_text(stopped / "archive.json"));

  // Killed in iteration 3, its qd.csv row written but checkpointed only at 2:
  // resumed from the checkpoint, the run ends as the uninterrupted one.
  SmallRun every2;
  every2.config.save.checkpoint_every = 2;
  MapElitesOptions crash;
  crash.on_iteration = [](const MapElitesProgress& p) {
    if (p.iteration == 3) throw std::runtime_error("killed");
  };
  CHECK_THROWS_WITH(run_map_elites(crashed, every2.config, every2.me, threads1, crash), "killed");
  CHECK(archive_file_text(crashed / "qd.csv").find("\n3,") != std::string::npos);
  run_map_elites(crashed, every2.config, every2.me, threads2, {});
  CHECK(archive_file_text(one / "qd.csv") == archive_file_text(crashed / "qd.csv"));
  CHECK(archive_file_text(one / "archive.json") == archive_file_text(crashed / "archive.json"));

  // Elites carry their replica estimates; insertion resampled some of them.
  const nlohmann::json archive = nlohmann::json::parse(archive_file_text(one / "archive.json"));
  REQUIRE(archive["cells"].size() == a.metrics.filled);
  long long gathered = 0;
  for (const auto& cell : archive["cells"]) {
    const long long n = cell["fitness"]["n"].get<long long>();
    CHECK(n >= 2);
    CHECK(n <= 4);
    if (n > 2) ++gathered;
  }
  CHECK(gathered > 0);
  // Every elite is written, and each reads back as a model whose exact run walks its logged distance.
  for (const auto& cell : archive["cells"]) {
    const soda::ModelDef prepared = soda::read_model_file(one / cell["file"].get<std::string>()).def;
    const Evaluation e = walk_problem_of(run.config).rollouts({&prepared}).front();
    CHECK(e.distance == cell["distance"].get<double>());
  }
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00000.json"));
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00002.json"));
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00004.json"));
}

TEST_CASE("run config: /algorithm and /map_elites read, resolve and round-trip, misuse names the pointer",
          "[map-elites][config]") {
  const RunConfig c = parse_run_config(R"({"population": {"random_fraction": 1}, "algorithm": "map-elites", "map_elites": {"batch_size": 7,
      "descriptors": ["floor_contact", "centroid_height"], "bins": [3, 9], "ranges": [[0, 1], [0, 90]]}})",
                                       "me.json", "/nowhere");
  CHECK(c.algorithm == AlgorithmKind::MapElites);
  CHECK(c.map_elites.batch_size == 7);
  REQUIRE(c.map_elites.axes.size() == 2);
  CHECK(c.map_elites.axes[1] == GridAxis{Descriptor::CentroidHeight, 9, 0.0, 90.0});
  CHECK(parse_run_config(to_json(c).dump(), "resolved", "/nowhere") == c);
  // A GA run's resolved config names neither key (its run folder is as before).
  const nlohmann::json ga = to_json(parse_run_config(R"({"population": {"random_fraction": 1}})", "ga.json", "/nowhere"));
  CHECK(!ga.contains("algorithm"));
  CHECK(!ga.contains("map_elites"));
  const auto error_of = [](const std::string& text) {
    try {
      parse_run_config(R"({"population": {"random_fraction": 1}, )" + text.substr(1), "x.json", "/nowhere");
    } catch (const soda::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error_of(R"({"algorithm": "cma-es"})") == "x.json: /algorithm: expected one of \"ga\" or \"map-elites\", got \"cma-es\"");
  CHECK(error_of(R"({"map_elites": {"batch_size": 3}})") ==
        "x.json: /map_elites: expected only with /algorithm \"map-elites\", got it with the GA");
  CHECK(error_of(R"({"algorithm": "map-elites", "map_elites": {"batch_size": 0}})") ==
        "x.json: /map_elites/batch_size: expected an integer in [1, 100000], got 0");
  CHECK_THAT(error_of(R"({"algorithm": "map-elites", "fitness": {"mode": "continuous"}})"),
             Catch::StartsWith("x.json: /algorithm: expected \"ga\" with /fitness/mode \"continuous\""));
}

TEST_CASE("corrected archive: every elite checked on fresh replicas, export --archive writes champions.json",
          "[map-elites]") {
  const SmallRun run;
  RunConfig config = run.config;
  config.algorithm = AlgorithmKind::MapElites;
  config.map_elites = run.me;
  config.map_elites.iterations = 2;
  config.map_elites.check_replicas = 3;
  const auto dir = run_dir("checked");
  RunStore::create(dir, config, true, "test");
  ThreadEvaluator threads(2);
  run_map_elites(dir, config, config.map_elites, threads, {});
  const CheckedArchive checked = write_checked_archive(dir, 2);

  const nlohmann::json archive = nlohmann::json::parse(archive_file_text(dir / "archive.json"));
  const nlohmann::json j = nlohmann::json::parse(archive_file_text(dir / "archive_checked.json"));
  REQUIRE(j["cells"].size() == archive["cells"].size());
  CHECK(j["check_replicas"] == 3);
  std::size_t ok = 0;
  for (std::size_t i = 0; i < archive["cells"].size(); ++i) {
    const nlohmann::json& a = archive["cells"][i];
    const nlohmann::json& c = j["cells"][i];
    CHECK(c["cell"] == a["cell"]);
    CHECK(c["id"] == a["id"]);
    CHECK(c["file"] == a["file"]);
    if (!c.contains("check")) continue;
    ++ok;
    CHECK(c["selection"]["n"] == a["fitness"]["n"]);
    CHECK(c["selection"]["mean"] == a["fitness"]["mean"]);
    CHECK(c["check"]["n"] == 3);
    CHECK(c["exact_distance"] == a["distance"]);
  }
  CHECK(ok == checked.checked.filled);
  CHECK(checked.selection.filled == archive["cells"].size());
  CHECK(std::isfinite(checked.mean_winners_curse));

  // The first elite by hand: its genome prepared, 3 runs with the check's seeds.
  const GridArchive elites = read_run_archive(dir, config);
  const ArchiveEntry& first = elites.elites().begin()->second;
  const WalkProblem problem = walk_problem_of(config);
  const soda::ModelDef prepared = problem.prepare(first.creature);
  double sum = 0.0;
  for (int r = 0; r < 3; ++r) {
    const soda::SineJitter jitter{replica_seed(config.seed, ReplicaPurpose::Check, creature_key(first.creature), r),
                                  config.fitness.jitter};
    sum += problem.rollouts({Rollout(&prepared, jitter)}).front().distance;
  }
  REQUIRE(j["cells"][0].contains("check"));
  CHECK(j["cells"][0]["check"]["mean"].get<double>() == Approx(sum / 3));
  CHECK(j["cells"][0]["checked_fitness"].get<double>() == Approx(sum / 3)); // walking right: fitness = distance

  // export --archive: every elite, and the same checks in champions.json.
  const auto out = run_dir("checked_export");
  const test::ShellResult r = test::run_sodaevo("export " + dir.string() + " --archive --check-replicas 3 --threads 1 --out " +
                                                out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json champions = nlohmann::json::parse(archive_file_text(out / "champions.json"));
  REQUIRE(champions.size() == j["cells"].size());
  for (std::size_t i = 0; i < champions.size(); ++i) {
    nlohmann::json expected = j["cells"][i];
    expected.erase("checked_fitness");
    expected["file"] = champions[i]["file"];
    CHECK(champions[i] == expected);
    CHECK(std::filesystem::exists(out / champions[i]["file"].get<std::string>()));
  }
  CHECK(std::filesystem::exists(out / "archive.json"));
}

TEST_CASE("bench qd: MAP-Elites and the GA at equal evaluations, both as archives of the same grid", "[map-elites]") {
  SmallRun run;
  bench::QdOptions qo;
  qo.config = run.config;
  qo.config.algorithm = AlgorithmKind::MapElites;
  qo.config.map_elites = run.me;
  qo.config_name = "small";
  qo.seeds = {3};
  qo.iterations = 2;
  qo.check_replicas = 2;
  qo.threads = 2;
  qo.work_dir = run_dir("bench_qd");
  const std::vector<bench::QdRow> rows = bench::run_qd_bench(qo);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].algorithm == "map-elites");
  CHECK(rows[1].algorithm == "ga");
  // The GA stops before a generation that would pass MAP-Elites' evaluations.
  CHECK(rows[1].evaluations <= rows[0].evaluations);
  CHECK(rows[1].evaluations > rows[0].evaluations / 2);
  CHECK(rows[0].metrics.cells == 36);
  CHECK(rows[1].metrics.cells == 36);
  CHECK(rows[0].metrics.filled >= rows[1].metrics.filled);
  CHECK(rows[0].best_checked != 0.0);
  CHECK(rows[1].best_checked != 0.0);
  const std::string csv = bench::qd_csv(rows);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
  CHECK_THAT(bench::qd_markdown(rows, qo, "test"), Catch::Contains("| map-elites (mean) |"));
  // A GA config is refused with the pointer.
  qo.config.algorithm = AlgorithmKind::Genetic;
  CHECK_THROWS_WITH(bench::run_qd_bench(qo), Catch::StartsWith("small: /algorithm: expected \"map-elites\""));
}

namespace {

/// Ten elites in a row of cells, e<i> with fitness i (the parent tests below): the
/// first `recent` entered their cells at iteration 10, the rest at iteration 1.
GridArchive ten_elites_in_a_row(int recent = 0) {
  const soda::ModelDef walker = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  GridArchive archive({{Descriptor::Width, 10, 0.0, 100.0}, {Descriptor::Height, 1, 0.0, 1.0}});
  for (int i = 0; i < 10; ++i) {
    ArchiveEntry e;
    e.id = "e" + std::to_string(i);
    e.creature = walker;
    e.fitness = estimate(1, static_cast<double>(i));
    e.iteration = i < recent ? 10 : 1;
    archive.place(static_cast<std::size_t>(i), e);
  }
  return archive;
}

} // namespace

TEST_CASE("parent tournament: parents drawn from fitter elites, plain MAP-Elites draws uniformly", "[map-elites]") {
  const RunConfig config = test::walker_run_config("t", 4, 8, 1, 300, 40);
  const GridArchive archive = ten_elites_in_a_row();
  const auto mean_parent = [&](int tournament) {
    MapElitesConfig me;
    me.batch_size = 400;
    me.parent_tournament = tournament;
    double sum = 0.0;
    for (const Individual& child : map_elites_children(config, me, archive, 1)) sum += std::stoi(child.parents[0].substr(1));
    return sum / me.batch_size;
  };
  // Uniform: about 4.5. The fittest of 3 draws of 0..9: E = sum_i i * ((i+1)^3 - i^3) / 1000 = 6.975.
  CHECK(mean_parent(1) == Approx(4.5).margin(0.5));
  CHECK(mean_parent(3) == Approx(6.975).margin(0.4));
}

TEST_CASE("elite pool: the elite share breeds from the fittest elites, or from the fittest recent entrants", "[map-elites]") {
  const RunConfig config = test::walker_run_config("t", 4, 8, 1, 300, 40);
  // e0..e4 entered at iteration 10 (recent), e5..e9 (the fittest) at iteration 1.
  const GridArchive archive = ten_elites_in_a_row(5);
  const auto parents = [&](double share, int pool, int recent) {
    MapElitesConfig me;
    me.batch_size = 200;
    me.elite_share = share;
    me.elite_pool = pool;
    me.elite_recent = recent;
    std::vector<int> out;
    for (const Individual& child : map_elites_children(config, me, archive, 12)) out.push_back(std::stoi(child.parents[0].substr(1)));
    return out;
  };
  // The first half from the pool of the 3 fittest (e7, e8, e9), the rest from all.
  std::vector<int> p = parents(0.5, 3, 0);
  CHECK(std::all_of(p.begin(), p.begin() + 100, [](int i) { return i >= 7; }));
  CHECK(std::any_of(p.begin() + 100, p.end(), [](int i) { return i < 7; }));
  // Recent within 2 iterations of iteration 12 (entered at 10 or later): the pool is
  // the 3 fittest of e0..e4 (e2, e3, e4).
  p = parents(0.5, 3, 2);
  CHECK(std::all_of(p.begin(), p.begin() + 100, [](int i) { return i >= 2 && i <= 4; }));
  // A window that reaches no entrant (iteration 10 is 2 before 12, not within 1):
  // the fittest of all again.
  p = parents(0.5, 3, 1);
  CHECK(std::all_of(p.begin(), p.begin() + 100, [](int i) { return i >= 7; }));
  // A pool larger than the recent entrants is topped up with the fittest of the rest.
  p = parents(1.0, 7, 2);
  CHECK(std::all_of(p.begin(), p.end(), [](int i) { return i <= 4 || i >= 8; }));
  CHECK(std::any_of(p.begin(), p.end(), [](int i) { return i == 9; }));
}
