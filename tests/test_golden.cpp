// The engine against the original: golden traces recorded from the 2003 Soda
// simulator (tests/data/soda/golden, copied from ../shared/models/soda/golden).
//
// Expected figures come from golden/README.md, not from this engine: the number of
// leading rows a faithful port (glibc sin, no FMA) reproduces bit for bit, the
// 1e-5 px bound over frames 0..300, and the 10,000-frame centroid displacements.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "core/step.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;

namespace {

struct TraceComparison {
  long long bit_exact_rows = 0; ///< leading rows equal in every bit
  double max_position_error = 0.0; ///< over the compared frames
  double max_velocity_error = 0.0;
  bool modes_match = true;
};

TraceComparison compare_with_trace(const std::string& name, long long compare_frames) {
  Scene scene = load_scene(golden_dir() / (name + ".xml"));
  const std::vector<GoldenRow> rows = read_golden_trace(golden_dir() / (name + ".trace.txt"));
  REQUIRE(rows.size() > 1);
  soda::State state = soda::make_state(scene.model);
  TraceComparison c;
  bool exact_so_far = true;
  for (std::size_t f = 0; f < rows.size(); ++f) {
    if (f > 0) soda::step(scene.model, state);
    const std::vector<double> ours = state_values(scene.model, state);
    const GoldenRow& gold = rows[f];
    REQUIRE(ours.size() == gold.values.size());
    bool exact = same_bits(state.wave_phase, gold.wave_phase) &&
                 static_cast<int>(state.wave_mode) == gold.wave_mode;
    for (std::size_t k = 0; k < ours.size(); ++k) exact = exact && same_bits(ours[k], gold.values[k]);
    if (exact_so_far && exact) ++c.bit_exact_rows;
    exact_so_far = exact_so_far && exact;
    if (static_cast<long long>(f) <= compare_frames) {
      if (static_cast<int>(state.wave_mode) != gold.wave_mode) c.modes_match = false;
      for (std::size_t k = 0; k < ours.size(); ++k) {
        const double err = std::fabs(ours[k] - gold.values[k]);
        double& bucket = (k % 4 < 2) ? c.max_position_error : c.max_velocity_error;
        bucket = std::max(bucket, err);
      }
    }
  }
  return c;
}

} // namespace

TEST_CASE("golden traces: bit-exact prefix and 1e-5 px over 300 frames", "[golden]") {
  struct Case {
    const char* name;
    long long min_bit_exact_rows; // golden/README.md, "rows bit-exact in a faithful port"
  };
  const Case cases[] = {{"dw_v1_container651", 372}, {"random_5", 54},  {"random_16", 301},
                        {"random_19", 37},           {"random_26", 56}, {"random_49", 17}};
  for (const Case& k : cases) {
    SECTION(k.name) {
      const TraceComparison c = compare_with_trace(k.name, 300);
      INFO(k.name << ": bit-exact rows " << c.bit_exact_rows << ", max position error "
                  << c.max_position_error << " px, max velocity error " << c.max_velocity_error);
      CHECK(c.bit_exact_rows >= k.min_bit_exact_rows);
      CHECK(c.max_position_error <= 1e-5);
      CHECK(c.max_velocity_error <= 1e-5);
      CHECK(c.modes_match);
    }
  }
}

TEST_CASE("golden centroid runs: 10,000 frames within 1 px", "[golden]") {
  const char* names[] = {"dw_v1_wide100000_noautorev", "carefulslug_v2converted_wide100000",
                         "monster_truck_v2converted_wide100000"};
  for (const char* name : names) {
    SECTION(name) {
      Scene scene = load_scene(golden_dir() / (std::string(name) + ".xml"));
      const auto rows = read_golden_centroids(golden_dir() / (std::string(name) + ".centroid.txt"));
      REQUIRE(rows.size() == 101);
      soda::State state = soda::make_state(scene.model);
      double worst = 0.0;
      for (const GoldenCentroid& row : rows) {
        soda::run(scene.model, state, row.frame - state.frame);
        const soda::Point2 c = soda::mass_centroid(scene.model, state);
        worst = std::max({worst, std::fabs(c.x - row.mean_x), std::fabs(c.y - row.mean_y)});
        CHECK(static_cast<int>(state.wave_mode) == row.wave_mode);
      }
      const soda::Point2 end = soda::mass_centroid(scene.model, state);
      INFO(name << ": frame 10000 meanX " << end.x << " vs " << rows.back().mean_x << "; worst over the run " << worst);
      CHECK(std::fabs(end.x - rows.back().mean_x) <= 1.0);
      CHECK(std::fabs(end.y - rows.back().mean_y) <= 1.0);
    }
  }
}
