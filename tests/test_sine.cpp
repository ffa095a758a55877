// The engine's sine (core/sine.hpp) against Java's Math.sin as the JVM computed it
// (tests/data/javasin: 223,943 arguments), and every other path to it (the vector
// kernels at each SIMD level) against the same golden bits.
#include <catch2/catch.hpp>
#include <zlib.h>

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
double from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

struct GoldenSine {
  std::string set;
  double x;
  std::uint64_t math_sin; ///< Math.sin(x)'s bits
};

const std::vector<GoldenSine>& golden_sines() {
  static const std::vector<GoldenSine> rows = [] {
    std::vector<GoldenSine> out;
    const std::string path = (sodaevo::test::data_dir() / "javasin" / "math_sin.tsv.gz").string();
    gzFile f = gzopen(path.c_str(), "rb");
    if (f == nullptr) throw std::runtime_error(path + ": cannot open");
    char line[256];
    while (gzgets(f, line, sizeof line) != nullptr) {
      if (line[0] == '#') continue;
      char set[32];
      unsigned long long x = 0, m = 0, s = 0;
      if (std::sscanf(line, "%31s %llx %llx %llx", set, &x, &m, &s) != 4) continue;
      out.push_back({set, from_bits(x), m});
    }
    gzclose(f);
    return out;
  }();
  return rows;
}

bool above_range(double x) { return std::isfinite(x) && std::fabs(x) > soda::sine_range_end(); }

} // namespace

TEST_CASE("soda::sine equals Java's Math.sin on every golden argument", "[sine]") {
  const std::vector<GoldenSine>& rows = golden_sines();
  REQUIRE(rows.size() == 223943);
  std::map<std::string, std::pair<int, int>> per_set; // equal, compared
  int refused = 0;
  for (const GoldenSine& g : rows) {
    if (above_range(g.x)) { // the routine's multi-precision path, not repeated: NaN
      CHECK(std::isnan(soda::sine(g.x)));
      ++refused;
      continue;
    }
    auto& [equal, compared] = per_set[g.set];
    ++compared;
    if (bits(soda::sine(g.x)) == g.math_sin) {
      ++equal;
    } else if (compared - equal <= 3) {
      FAIL_CHECK(g.set << ": sine(" << std::hexfloat << g.x << ") = " << soda::sine(g.x) << ", Math.sin gives "
                       << from_bits(g.math_sin));
    }
  }
  for (const auto& [set, counts] : per_set) {
    INFO(set << ": " << counts.first << " of " << counts.second << " equal");
    CHECK(counts.first == counts.second);
  }
  CHECK(per_set["uniform"].second == 100000);
  CHECK(per_set["muscle"].second == 100000);
  CHECK(per_set["differ"].second == 5992);
  CHECK(refused == 3); // 90112, 1e5, 1e22: the edge set's only arguments above the range
}

TEST_CASE("the vector kernels give Math.sin's bits at every SIMD level", "[sine]") {
  const std::vector<GoldenSine>& rows = golden_sines();
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
        const std::uint64_t want = above_range(g.x) ? bits(soda::sine(g.x)) : g.math_sin;
        bad += bits(out[static_cast<std::size_t>(i)]) == want ? 0 : 1;
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

TEST_CASE("soda::sine at the ends of its range: x below, NaN above, Java's NaNs", "[sine]") {
  const double end = soda::sine_range_end();
  CHECK(std::nextafter(end, 1e300) == 90112.0);
  CHECK(std::isfinite(soda::sine(end)));
  CHECK(std::isfinite(soda::sine(-end)));
  for (double v : {90112.0, -90112.0, 1e9, 1e300, -1e300}) {
    INFO(v);
    CHECK(std::isnan(soda::sine(v)));
  }
  // Below 2^-252 the routine gives x back, signed zeros and subnormals included.
  for (double v : {0.0, -0.0, 0x1p-1074, -0x1p-1074, 0x1p-1022, 0x1.fffffffffffffp-253, -0x1p-300}) {
    CHECK(bits(soda::sine(v)) == bits(v));
  }
  // x86's NaNs: infinity times -0 is the default NaN; a NaN comes back quieted.
  CHECK(bits(soda::sine(HUGE_VAL)) == 0xfff8000000000000ULL);
  CHECK(bits(soda::sine(-HUGE_VAL)) == 0xfff8000000000000ULL);
  CHECK(bits(soda::sine(from_bits(0x7ff0000000000001ULL))) == 0x7ff8000000000001ULL);
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
