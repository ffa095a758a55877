// The work-precision benchmark's own arithmetic (Kendall's tau against hand-counted
// pairs, the Welch interval and the predicted tau against hand-worked values), its
// replicas, and a smoke run of its quick mode.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "bench/accuracy_bench.hpp"
#include "bench/analytic_scenes.hpp"
#include "bench/replica_runs.hpp"
#include "core/model.hpp"
#include "core/stepping.hpp"
#include "test_support.hpp"

using namespace sodaevo;

TEST_CASE("kendall tau-b on hand-counted samples", "[accuracy]") {
  CHECK(bench::kendall_tau({1, 2, 3, 4}, {10, 20, 30, 40}) == Approx(1.0));
  CHECK(bench::kendall_tau({1, 2, 3, 4}, {4, 3, 2, 1}) == Approx(-1.0));
  // One swapped neighbour pair out of 6 pairs: (5 - 1) / 6.
  CHECK(bench::kendall_tau({1, 2, 3, 4}, {1, 3, 2, 4}) == Approx(4.0 / 6.0));
  // A tie in b: pairs 6, concordant 5, ties in b 1: 5 / sqrt(6 * 5).
  CHECK(bench::kendall_tau({1, 2, 3, 4}, {1, 2, 3, 3}) == Approx(5.0 / std::sqrt(30.0)));
  CHECK_THROWS(bench::kendall_tau({1, 2}, {1}));
}

TEST_CASE("predicted tau of two noisy estimates against the normal table", "[accuracy]") {
  // No noise: every pair ordered right.
  CHECK(bench::predicted_tau({1, 2, 3}, {0, 0, 0}) == 1.0);
  // One pair, gap 1, combined standard error 1: P(|Z| < 1) = 0.682689 (normal
  // table), squared for two independent estimates.
  CHECK(bench::predicted_tau({0, 1}, {std::sqrt(0.5), std::sqrt(0.5)}) == Approx(0.682689 * 0.682689).epsilon(1e-5));
  // Gap 1.96 standard errors: P(|Z| < 1.96) = 0.95.
  CHECK(bench::predicted_tau({0, 1.96}, {1, 0}) == Approx(0.95 * 0.95).epsilon(1e-4));
  // Equal means: a coin toss, tau 0.
  CHECK(bench::predicted_tau({5, 5}, {1, 1}) == 0.0);
}

TEST_CASE("difference of expected distances with its Welch interval, worked by hand", "[accuracy]") {
  bench::ExpectedDistance a, b;
  a.summary = summarize_sample({1, 2, 3}); // mean 2, sd 1
  a.standard_error = 1.0 / std::sqrt(3.0);
  b.summary = summarize_sample({4, 6}); // mean 5, sd sqrt(2)
  b.standard_error = 1.0;
  // se^2 = 1/3 + 1 = 4/3; Welch df = (4/3)^2 / ((1/3)^2 / 2 + 1^2 / 1) = 32/19 = 1.68,
  // rounded down to 1: t(0.975, 1) = 12.7062 (table).
  const bench::DifferenceInterval d = bench::difference_interval(a, b);
  CHECK(d.difference == -3.0);
  CHECK(d.high - d.difference == Approx(12.7062 * std::sqrt(4.0 / 3.0)).epsilon(1e-5));
  CHECK(d.difference - d.low == Approx(d.high - d.difference));
  // Many replicas each: df large, t near 1.96 (table: t(0.975, 60) = 2.0003).
  bench::ExpectedDistance c, e;
  c.summary.n = e.summary.n = 31;
  c.summary.mean = 10;
  e.summary.mean = 0;
  c.standard_error = e.standard_error = 1.0; // df = 4 / (1/30 + 1/30) = 60
  CHECK(bench::difference_interval(c, e).high == Approx(10 + 2.0003 * std::sqrt(2.0)).epsilon(1e-5));
  // No finite replica on one side: no interval.
  bench::ExpectedDistance none;
  CHECK(std::isnan(bench::difference_interval(none, a).difference));
}

TEST_CASE("expected distance: replica 0 is the exact run, the jittered replicas part from it", "[accuracy]") {
  // random_26 (a golden trace's random creature) is chaotic (tests/test_replicas.cpp).
  const soda::Model model = test::load_scene(test::golden_dir() / "random_26.xml").model;
  bench::ReplicaPlan plan;
  plan.checkpoints = {50, 100, 2100};
  plan.from = 1;
  plan.to = 2;
  plan.keep = 0;
  plan.replicas = 3;
  const bench::ExpectedDistance e = bench::expected_distance(model, soda::Stepping{}, plan);
  // Replica 0 against a plain exact run of the reference step.
  soda::State s = soda::make_state(model);
  soda::FrameStepper stepper(model, soda::Stepping{}, 2100, true);
  stepper.run(s, 100);
  const double start = soda::mass_centroid(model, s).x;
  stepper.run(s, 2000);
  REQUIRE(e.distances.size() == 3);
  CHECK(e.exact == Approx(soda::mass_centroid(model, s).x - start).margin(1e-9));
  CHECK(e.exact == e.distances[0]);
  CHECK(e.distances[1] != e.distances[0]); // 2000 frames part them
  CHECK(e.distances[2] != e.distances[1]);
  CHECK(e.summary.n == 3);
  CHECK(e.summary.mean == Approx((e.distances[0] + e.distances[1] + e.distances[2]) / 3.0));
  CHECK(e.standard_error == Approx(e.summary.sd / std::sqrt(3.0)));
  CHECK(e.diverged == 0);
}

TEST_CASE("accuracy benchmark quick run: every section, soda equals euler/1, rk4 converges", "[accuracy]") {
  bench::AccuracyOptions o;
  o.quick = true;
  o.classics = {{"dainty_walker", std::string(SODAEVO_MODELS_DIR) + "/dainty_walker.xml"}};
  // The champion section on a small walker: the treader (a GA champion) costs 10 s
  // of implicit sub-steps here and tests nothing more.
  o.champions = {{"dainty_again", std::string(SODAEVO_MODELS_DIR) + "/dainty_walker.xml"}};
  o.walkers = 6;
  const bench::AccuracyReport r = bench::run_accuracy_bench(o);
  int analytic = 0, classic = 0, champion = 0, walkers = 0;
  double soda_error = -1, euler1_error = -2, soda_mean = -1, euler1_mean = -2, rk4_1 = 0, rk4_8 = 0;
  for (const auto& row : r.rows) {
    analytic += row.section == "analytic";
    classic += row.section == "classic";
    champion += row.section == "champion";
    walkers += row.section == "walkers";
    if (row.section == "classic") {
      CHECK(row.error_low <= row.error_high);
      if (row.stepping.mode == soda::PhysicsMode::Soda) {
        soda_error = row.exact_error;
        soda_mean = row.distance;
      }
      if (row.stepping == soda::Stepping{soda::PhysicsMode::Continuous, soda::Integrator::Euler, 1}) {
        euler1_error = row.exact_error;
        euler1_mean = row.distance;
      }
    }
    if (row.section == "analytic" && row.scene == "single spring" &&
        row.stepping.integrator == soda::Integrator::Rk4 && row.stepping.mode == soda::PhysicsMode::Continuous) {
      if (row.stepping.substeps == 1) rk4_1 = row.position_error;
      if (row.stepping.substeps == 8) rk4_8 = row.position_error;
    }
  }
  const int settings = static_cast<int>(bench::swept_settings(8).size()); // quick: dt down to 1/8
  CHECK(analytic == static_cast<int>(bench::analytic_scenes().size()) * settings);
  CHECK(classic == settings);
  CHECK(champion == settings);
  CHECK(walkers == static_cast<int>(bench::swept_settings(4).size()));
  CHECK(r.replicas == 3);
  CHECK(r.references.size() == 2);
  // Jitter and all, euler/1 steps as soda does, replica for replica.
  CHECK(soda_error == euler1_error);
  CHECK(soda_mean == euler1_mean);
  CHECK(rk4_8 < rk4_1 / 1000.0); // order 4: 8^4 = 4096
}
