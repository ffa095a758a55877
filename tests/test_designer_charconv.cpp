// The WebAssembly build formats and parses numbers with printf_charconv.hpp (its
// C++ library lacks floating std::to_chars/from_chars). Held here against the
// standard functions of the native build, which are the reference: the same text
// for every kind of double, the same accept/reject and value for every kind of text.
#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/printf_charconv.hpp"

namespace {

std::string std_shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::optional<double> std_parse(const std::string& text) {
  double v = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

double from_bits(std::uint64_t bits) {
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

} // namespace

TEST_CASE("designer: printf_shortest writes what std::to_chars writes", "[designer][charconv]") {
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.1, 100.0, 1e15, 1e16, 1e20, 1e21, 1e-5, 1e-6,
                                123456789012345680.0, 5e-324, 1.5e300, 1234.5, 0.001, 55.0, 651.0,
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::denorm_min(), 0.3, 2.0 / 3.0, 9.5367431640625e-07};
  for (int e = -1074; e <= 1023; ++e) values.push_back(std::ldexp(1.0, e)); // powers of two: uneven gaps
  std::mt19937_64 rng(7);
  for (int i = 0; i < 60000; ++i) {
    const double v = from_bits(rng());
    if (std::isfinite(v)) values.push_back(v);
  }
  std::uniform_int_distribution<int> digits(0, 999999), exponent(-30, 30);
  for (int i = 0; i < 20000; ++i) values.push_back(digits(rng) * std::pow(10.0, exponent(rng))); // short decimals
  for (int i = 0; i < 20000; ++i) values.push_back(std::uniform_real_distribution<double>(-700, 700)(rng));
  // n / 10^p, as a design's numbers are ("20", "6.5", "0.125"): the fast path's.
  std::uniform_int_distribution<int> places(0, 22), count(1, 17);
  for (int i = 0; i < 60000; ++i) {
    const double n = std::floor(std::uniform_real_distribution<double>(0, 1)(rng) * std::pow(10.0, count(rng)));
    values.push_back((i % 2 ? -n : n) / std::pow(10.0, places(rng)));
  }
  for (double n : {4503599627370495.0, 4503599627370496.0, 9007199254740991.0, 9007199254740992.0, 99999999999999.99,
                   0.30000000000000004, 1e-7, 123e-9, 1.5e-17, 1e22, 1e23}) {
    values.push_back(n);
    values.push_back(std::nextafter(n, 0.0));
    values.push_back(std::nextafter(n, 1e300));
  }
  int differing = 0;
  for (double v : values) {
    const std::string ours = soda::printf_shortest(v), theirs = std_shortest(v);
    if (ours != theirs && ++differing <= 5) {
      INFO(theirs);
      CHECK(ours == theirs);
    }
  }
  CHECK(differing == 0);
}

TEST_CASE("designer: strtod_strict reads what std::from_chars reads", "[designer][charconv]") {
  std::vector<std::string> texts = {"0", "-0", "1", "-1", "1.", "-.5", ".5", ".", "-", "", ".e1", "1e", "1e+", "1e-",
                                    "1e5", "1E5", "1e+05", "0x10", "inf", "-inf", "nan", "infinity", "1e-400",
                                    "1e-310", "1e400", "0e999", "0.000e-999", "4.9e-324", "2.4e-324", "2.5e-324",
                                    "1.7976931348623157e308", "1.7976931348623159e308", "00012", "1_", " 1", "1 ",
                                    "+1", "--1", "1.2.3", "1e5.5", "12345678901234567890123456789", "0.1", "-0.0"};
  std::mt19937_64 rng(11);
  for (int i = 0; i < 100000; ++i) {
    const double v = from_bits(rng());
    if (std::isfinite(v)) texts.push_back(std_shortest(v));
  }
  // Short decimals in the forms files use (strtod_strict's fast path) and just past it.
  for (int i = 0; i < 100000; ++i) {
    const double v = std::uniform_real_distribution<double>(-1e4, 1e4)(rng) * std::pow(10.0, -static_cast<int>(rng() % 12));
    const char* forms[] = {"%.1f", "%.6f", "%.15g", "%.16g", "%.3e", "%.14e", "%.0f"};
    char buf[64];
    std::snprintf(buf, sizeof buf, forms[i % 7], v);
    texts.push_back(buf);
  }
  for (const char* t : {"0.0", "-0.0", "000.000", "1e22", "1e23", "-1e-22", "1e-23", "123456789012345", "1234567890123456",
                        "0.000000000000000000000012", "0e9999", "1e9999", "1e-9999", "12345.678e-10"}) {
    texts.push_back(t);
  }
  const std::string alphabet = "0123456789.e-+E";
  for (int i = 0; i < 100000; ++i) { // random junk around number syntax
    std::string t;
    const int n = 1 + static_cast<int>(rng() % 8);
    for (int k = 0; k < n; ++k) t.push_back(alphabet[rng() % alphabet.size()]);
    texts.push_back(t);
  }
  int differing = 0;
  for (const std::string& t : texts) {
    const auto ours = soda::strtod_strict(t), theirs = std_parse(t);
    const bool same = ours.has_value() == theirs.has_value() &&
                      (!ours || std::memcmp(&*ours, &*theirs, sizeof(double)) == 0);
    if (!same && ++differing <= 5) {
      INFO("'" << t << "': ours " << (ours ? std_shortest(*ours) : "refused") << ", from_chars "
               << (theirs ? std_shortest(*theirs) : "refused"));
      CHECK(same);
    }
  }
  CHECK(differing == 0);
}
