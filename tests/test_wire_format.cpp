// The wire format the MPI evaluator sends creatures, evaluations, problems and
// estimators in: exact round trips (every bit of every double) and clear errors
// on damaged messages.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <limits>

#include "evolve/estimators/estimator.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/algorithms/variation.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/problems/wire_format.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;

TEST_CASE("creatures round-trip the wire format bit for bit", "[wire]") {
  soda::ModelDef d = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  d.comment = "a comment with <xml> & \"quotes\"";
  d.name = "walker";
  d.nodes[0].x = -0.0;
  d.nodes[0].vx = std::nextafter(1.0, 2.0);
  d.nodes[1].vy = 5e-324;
  d.links[0].phase = 0.1 + 0.2;
  d.settings.autoreverse = false;
  d.settings.gravity_direction = soda::GravityDirection::Up;
  d.settings.wave_direction = soda::WaveDirection::Reverse;
  const soda::ModelDef back = decode_creature(encode_creature(d));
  CHECK(back == d);
  CHECK(std::signbit(back.nodes[0].x));
  CHECK(std::bit_cast<std::uint64_t>(back.nodes[1].vy) == std::bit_cast<std::uint64_t>(d.nodes[1].vy));
}

TEST_CASE("evaluations round-trip the wire format", "[wire]") {
  Evaluation e;
  e.status = EvaluationStatus::Diverged;
  e.reason = "diverged at frame 12";
  e.fitness = kWorstFitness;
  e.distance = 1.0 / 3.0;
  e.px_per_frame = -1e-300;
  const Evaluation back = decode_evaluation(encode_evaluation(e));
  CHECK(back.status == e.status);
  CHECK(back.reason == e.reason);
  CHECK(back.fitness == e.fitness);
  CHECK(back.distance == e.distance);
  CHECK(back.px_per_frame == e.px_per_frame);
}

TEST_CASE("damaged messages are refused with a WireError", "[wire]") {
  const soda::ModelDef d = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  std::vector<char> bytes = encode_creature(d);
  // Every truncation is caught, never a read past the end.
  for (std::size_t cut = 0; cut < bytes.size(); cut += 7) {
    const std::vector<char> part(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    CHECK_THROWS_AS(decode_creature(part), WireError);
  }
  std::vector<char> longer = bytes;
  longer.push_back(0);
  CHECK_THROWS_AS(decode_creature(longer), WireError);
  // A huge string length is refused before any allocation.
  std::vector<char> huge = bytes;
  for (int i = 0; i < 8; ++i) huge[static_cast<std::size_t>(i)] = static_cast<char>(0xff);
  CHECK_THROWS_AS(decode_creature(huge), WireError);
  std::vector<char> bad_status = encode_evaluation(Evaluation{});
  bad_status[0] = 9;
  CHECK_THROWS_WITH(decode_evaluation(bad_status), Catch::Contains("bad evaluation status"));
}

TEST_CASE("an evaluation's honesty change and estimate cross the wire", "[wire]") {
  Evaluation e;
  e.status = EvaluationStatus::Ok;
  e.fitness = 12.5;
  e.honesty_change = -0.25;
  e.estimate = {7, 12.0, std::nextafter(0.5, 1.0), -0.0};
  e.descriptors = {5.0, 1.0 / 3.0, -0.0};
  const Evaluation back = decode_evaluation(encode_evaluation(e));
  CHECK(back.honesty_change == -0.25);
  CHECK(back.estimate == e.estimate);
  CHECK(std::signbit(back.estimate.median));
  CHECK(back.descriptors == e.descriptors);
  CHECK(std::signbit(back.descriptors[2]));
  // A damaged descriptor count is refused before any allocation.
  std::vector<char> bytes = encode_evaluation(e);
  const std::size_t count_at = bytes.size() - 3 * 8 - 4;
  bytes[count_at + 3] = static_cast<char>(0x7f);
  CHECK_THROWS_WITH(decode_evaluation(bytes), Catch::Contains("descriptors, expected at most 64"));
}

namespace {

/// A problem with every setting away from its default.
WalkProblem unusual_problem() {
  FitnessConfig f;
  f.frames = 321;
  f.settle_frames = 17;
  f.direction = WalkDirection::Either;
  f.scaling = FitnessScaling::None;
  f.drop_height = 0.1 + 0.2;
  f.mode = soda::PhysicsMode::Continuous;
  f.integrator = soda::Integrator::ImplicitMidpoint;
  f.substeps = 3;
  f.divergence = DivergenceCheck::Energy;
  f.honesty_max_change = 0.125;
  f.honesty_substeps_factor = 5;
  f.stability_margin_min = 1.5;
  WorldConfig w;
  w.gravity = 0.5;
  w.friction = 0.01;
  w.springyness = 0.25;
  w.surface_friction = 0.75;
  w.surface_reflection = -0.5;
  w.gravity_direction = soda::GravityDirection::Up;
  w.evolve = {"friction", "surface_reflection"};
  LimitsConfig l;
  l.min_masses = 4;
  l.max_masses = 9;
  l.max_links = 33;
  return WalkProblem(f, w, l, 9);
}

} // namespace

TEST_CASE("a problem and an estimator cross the wire as they are", "[wire]") {
  const WalkProblem problem = unusual_problem();
  WireWriter w;
  problem.write(w);
  SingleRollout().write(w);
  WireReader r(w.bytes());
  const std::unique_ptr<Problem> problem_back = read_problem(r);
  const std::unique_ptr<Estimator> estimator_back = read_estimator(r);
  r.expect_end();
  REQUIRE(problem_back->kind() == "walk");
  const auto& walk = dynamic_cast<const WalkProblem&>(*problem_back);
  CHECK(walk.fitness() == problem.fitness());
  CHECK(walk.world() == problem.world());
  CHECK(walk.limits() == problem.limits());
  CHECK(walk.describe_every() == 9);
  CHECK(estimator_back->kind() == "single");
  // A replica estimator on a range of replicas (MAP-Elites' further replicas).
  ReplicaPlan plan;
  plan.replicas = 3;
  plan.first_replica = 5;
  plan.replicas_max = 12;
  plan.statistic = EstimateStatistic::Median;
  plan.jitter = 0.125;
  plan.run_seed = 77;
  WireWriter e;
  ReplicaEstimator(plan).write(e);
  WireReader er(e.bytes());
  const std::unique_ptr<Estimator> replicas_back = read_estimator(er);
  er.expect_end();
  CHECK(dynamic_cast<const ReplicaEstimator&>(*replicas_back).plan() == plan);
}

TEST_CASE("a damaged problem or estimator is refused with what was wrong", "[wire]") {
  WireWriter w;
  unusual_problem().write(w);
  const std::vector<char> bytes = w.bytes();
  auto read = [](const std::vector<char>& b) {
    WireReader r(b);
    return read_problem(r);
  };
  // The kind tag: u64 length 4, then "walk".
  std::vector<char> unknown = bytes;
  unknown[8] = 'r';
  CHECK_THROWS_WITH(read(unknown), Catch::Contains("unknown problem kind 'ralk'"));
  // The direction follows the tag and the two frame counts.
  std::vector<char> bad_direction = bytes;
  bad_direction[12 + 16] = 7;
  CHECK_THROWS_WITH(read(bad_direction), Catch::Contains("bad direction value 7"));
  const std::vector<char> cut(bytes.begin(), bytes.end() - 1);
  CHECK_THROWS_AS(read(cut), WireError);
  WireWriter e;
  e.text("median-of-3");
  WireReader r(e.bytes());
  CHECK_THROWS_WITH(read_estimator(r), Catch::Contains("unknown estimator kind 'median-of-3'"));
}
