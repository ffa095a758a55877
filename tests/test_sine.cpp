// The engine's sine (core/sine.hpp) against Java's Math.sin as the JVM computed it
// (tests/data/javasin: 223,943 arguments below 90112 and at the edges, 58,090 above),
// and every other path to it (the vector kernels at each SIMD level) against the
// same golden bits.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/exact_sines.hpp"
#include "core/simd_level.hpp"
#include "core/sine.hpp"
#include "test_support.hpp"

// The same source compiled with contraction and FMA on (tests/CMakeLists.txt):
// the build's -ffp-contract=off is what keeps the engine's sine Java's.
namespace soda {
double contracted_sine(double x);
}

namespace {

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }
double sine_from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

struct GoldenSine {
  std::string set;
  double x;
  std::uint64_t math_sin; ///< Math.sin(x)'s bits
};

/// Rows `set x math_sin [...]` of a gzipped golden file in tests/data/javasin.
std::vector<GoldenSine> read_golden_sines(const std::string& file) {
  std::vector<GoldenSine> out;
  for (const std::string& line : sodaevo::test::read_lines(sodaevo::test::data_dir() / "javasin" / file)) {
    if (line.empty() || line[0] == '#') continue;
    char set[32];
    unsigned long long x = 0, m = 0;
    if (std::sscanf(line.c_str(), "%31s %llx %llx", set, &x, &m) != 3) continue;
    out.push_back({set, sine_from_bits(x), m});
  }
  return out;
}

/// math_sin.tsv.gz (made with the JVM for the issue; README there).
const std::vector<GoldenSine>& golden_sines() {
  static const std::vector<GoldenSine> rows = read_golden_sines("math_sin.tsv.gz");
  return rows;
}

/// large_sin.tsv.gz: |x| >= 90112 (LargeSin.java there).
const std::vector<GoldenSine>& golden_large_sines() {
  static const std::vector<GoldenSine> rows = read_golden_sines("large_sin.tsv.gz");
  return rows;
}

/// Counts per set of rows where `sine_of(x)` has Math.sin's bits; reports the first few that do not.
template <class Sine>
std::map<std::string, std::pair<int, int>> compare_sets(const std::vector<GoldenSine>& rows, Sine&& sine_of) {
  std::map<std::string, std::pair<int, int>> per_set; // equal, compared
  for (const GoldenSine& g : rows) {
    auto& [equal, compared] = per_set[g.set];
    ++compared;
    const double got = sine_of(g.x);
    if (bits(got) == g.math_sin) {
      ++equal;
    } else if (compared - equal <= 3) {
      FAIL_CHECK(g.set << ": sine(" << std::hexfloat << g.x << ") = " << got << ", Math.sin gives "
                       << sine_from_bits(g.math_sin));
    }
  }
  for (const auto& [set, counts] : per_set) {
    INFO(set << ": " << counts.first << " of " << counts.second << " equal");
    CHECK(counts.first == counts.second);
  }
  return per_set;
}

} // namespace

TEST_CASE("soda::sine equals Java's Math.sin on every golden argument", "[sine]") {
  const std::vector<GoldenSine>& rows = golden_sines();
  REQUIRE(rows.size() == 223943);
  auto per_set = compare_sets(rows, [](double x) { return soda::sine(x); });
  CHECK(per_set["uniform"].second == 100000);
  CHECK(per_set["muscle"].second == 100000);
  CHECK(per_set["differ"].second == 5992);
  CHECK(per_set["edge"].second == 17951);
}

TEST_CASE("soda::sine equals Java's Math.sin above 90112 (the large-argument reduction)", "[sine]") {
  const std::vector<GoldenSine>& rows = golden_large_sines();
  REQUIRE(rows.size() == 58090);
  auto per_set = compare_sets(rows, [](double x) { return soda::sine(x); });
  CHECK(per_set["large"].second == 30000);    // log-uniform magnitudes, both signs
  CHECK(per_set["exponent"].second == 8060);  // every exponent from 16 to 1023
  CHECK(per_set["quarterpi"].second == 20000); // next to multiples of pi/4: the deepest cancellation
}

TEST_CASE("the vector kernels give Math.sin's bits at every SIMD level", "[sine]") {
  std::vector<GoldenSine> rows = golden_sines();
  rows.insert(rows.end(), golden_large_sines().begin(), golden_large_sines().end());
  std::vector<double> args;
  for (const GoldenSine& g : rows) args.push_back(g.x);
  std::vector<double> out(args.size());
  for (soda::SimdLevel level : {soda::SimdLevel::Sse2, soda::SimdLevel::Avx2, soda::SimdLevel::Avx512}) {
    if (!soda::simd_level_supported(level)) {
      WARN("vector sines at " << soda::simd_level_name(level) << " skipped: not supported by this CPU");
      continue;
    }
    // Offsets 0..2: every argument meets every lane of a vector.
    for (int offset = 0; offset < 3; ++offset) {
      const int n = static_cast<int>(args.size()) - offset;
      soda::exact_sines(args.data() + offset, out.data(), n, level);
      int bad = 0;
      for (int i = 0; i < n; ++i) {
        const GoldenSine& g = rows[static_cast<std::size_t>(i + offset)];
        bad += bits(out[static_cast<std::size_t>(i)]) == g.math_sin ? 0 : 1;
      }
      INFO(soda::simd_level_name(level) << ", offset " << offset);
      CHECK(bad == 0);
    }
  }
  // The scalar loop that the stepper option vector_sines = false takes.
  std::vector<double> scalar(args.size());
  soda::scalar_sines(args.data(), scalar.data(), static_cast<int>(args.size()));
  int bad = 0;
  for (std::size_t i = 0; i < args.size(); ++i) bad += bits(scalar[i]) == bits(soda::sine(args[i])) ? 0 : 1;
  CHECK(bad == 0);
}

TEST_CASE("soda::sine at the ends: x below 2^-252, Java's NaNs", "[sine]") {  // Below 2^-252 the routine gives x back, signed zeros and subnormals included.
  for (double v : {0.0, -0.0, 0x1p-1074, -0x1p-1074, 0x1p-1022, 0x1.fffffffffffffp-253, -0x1p-300}) {
    CHECK(bits(soda::sine(v)) == bits(v));
  }
  // x86's NaNs: infinity times -0 is the default NaN; a NaN comes back quieted.
  CHECK(bits(soda::sine(HUGE_VAL)) == 0xfff8000000000000ULL);
  CHECK(bits(soda::sine(-HUGE_VAL)) == 0xfff8000000000000ULL);
  CHECK(bits(soda::sine(sine_from_bits(0x7ff0000000000001ULL))) == 0x7ff8000000000001ULL);
}

TEST_CASE("contraction into fused multiply-adds would break the sine", "[sine]") {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("fma")) {
    WARN("skipped: this CPU has no fused multiply-add");
    return;
  }
  // The engine's sine compiled with -ffp-contract=fast -mfma differs from Math.sin
  // on some muscle arguments (about 0.1 %): the golden test above is sensitive to
  // contraction, and -ffp-contract=off (CMakeLists.txt) is needed.
  int differ = 0, compared = 0;
  for (const GoldenSine& g : golden_sines()) {
    if (g.set != "muscle") continue;
    ++compared;
    differ += bits(soda::contracted_sine(g.x)) == g.math_sin ? 0 : 1;
  }
  INFO(differ << " of " << compared << " muscle arguments differ with contraction");
  CHECK(differ > 10);
#else
  WARN("skipped: not an x86-64 build");
#endif
}
