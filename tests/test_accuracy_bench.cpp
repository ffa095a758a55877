// The work-precision benchmark's own arithmetic (Kendall's tau against hand-counted
// pairs) and a smoke run of its quick mode.
#include <catch2/catch.hpp>

#include <string>

#include "bench/accuracy_bench.hpp"
#include "bench/analytic_scenes.hpp"
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

TEST_CASE("accuracy benchmark quick run: every section, soda equals euler/1, rk4 converges", "[accuracy]") {
  bench::AccuracyOptions o;
  o.quick = true;
  o.classics = {{"dainty_walker", std::string(SODAEVO_MODELS_DIR) + "/dainty_walker.xml"}};
  o.walkers = 6;
  const bench::AccuracyReport r = bench::run_accuracy_bench(o);
  int analytic = 0, classic = 0, walkers = 0;
  double soda_error = -1, euler1_error = -2, rk4_1 = 0, rk4_8 = 0;
  for (const auto& row : r.rows) {
    analytic += row.section == "analytic";
    classic += row.section == "classic";
    walkers += row.section == "walkers";
    if (row.section == "classic") {
      if (row.stepping.mode == soda::PhysicsMode::Soda) soda_error = row.distance_error;
      if (row.stepping == soda::Stepping{soda::PhysicsMode::Continuous, soda::Integrator::Euler, 1}) {
        euler1_error = row.distance_error;
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
  CHECK(walkers == settings);
  CHECK(soda_error == euler1_error);
  CHECK(rk4_8 < rk4_1 / 1000.0); // order 4: 8^4 = 4096
}
