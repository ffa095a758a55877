#include "printf_charconv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cstdint>

namespace soda {

namespace {

/// A decimal d1.d2d3... x 10^exponent, digits without sign or point.
struct Decimal {
  std::string digits;
  int exponent = 0;
};

/// Exact powers of ten: 10^22 is the largest a double holds exactly.
constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/// The shortest digits of a (positive, finite) when it is n / 10^p for a small p,
/// as the numbers of a design mostly are ("20", "6.5", "0.125"), without printf or
/// strtod (each try of shortest_digits costs microseconds in WebAssembly: seconds
/// for a 5,000-mass design). n / 10^p == a (both exact, so the division rounds the
/// rational n / 10^p as strtod rounds the decimal) says the decimal reads back. The
/// least such p gives the fewest digits; the exact nearest integer to a * 10^p is
/// within one of the rounded product (under 2^52), so three candidates cover it, and
/// a p where two read back is left to shortest_digits (digits beyond the double's
/// precision, where the nearest must be picked). False: not such a number.
bool short_decimal_digits(double a, Decimal& out) {
  for (int p = 0; p <= 17; ++p) {
    const double x = a * kPow10[p];
    if (!(x < 4503599627370496.0)) return false; // 2^52
    const double m = std::nearbyint(x);
    double found = 0.0;
    int reading_back = 0;
    for (const double n : {m - 1.0, m, m + 1.0}) {
      if (n > 0.0 && n / kPow10[p] == a) {
        found = n;
        ++reading_back;
      }
    }
    if (reading_back > 1) return false;
    if (reading_back == 1) {
      out.digits = std::to_string(static_cast<std::uint64_t>(found));
      out.exponent = static_cast<int>(out.digits.size()) - 1 - p;
      return true;
    }
  }
  return false;
}

/// What strtod gives for text of from_chars' syntax (checked) when its digits make
/// an integer n < 10^15 and its point and exponent a power 10^k with |k| <= 22:
/// n * 10^k or n / 10^-k, one correctly rounded operation on exact operands, which
/// is the correctly rounded value strtod gives (the numbers of a design: "20.0",
/// "6.5"; strtod costs microseconds in WebAssembly). Nullopt: not such text.
std::optional<double> short_decimal_value(std::string_view text) {
  std::size_t i = 0;
  const bool negative = !text.empty() && text[0] == '-';
  if (negative) ++i;
  std::uint64_t n = 0;
  int digits = 0, scale = 0; // significant digits in n; the power of ten n carries
  bool point = false;
  for (; i < text.size() && text[i] != 'e' && text[i] != 'E'; ++i) {
    if (text[i] == '.') {
      point = true;
      continue;
    }
    if (n == 0 && text[i] == '0') { // a leading zero adds no digit
      if (point) --scale;
      continue;
    }
    if (++digits > 15) return std::nullopt;
    n = 10 * n + static_cast<std::uint64_t>(text[i] - '0');
    if (point) --scale;
  }
  if (i < text.size()) { // the exponent, at most four digits
    ++i;
    const bool below = i < text.size() && text[i] == '-';
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
    if (text.size() - i > 4) return std::nullopt;
    int e = 0;
    for (; i < text.size(); ++i) e = 10 * e + (text[i] - '0');
    scale += below ? -e : e;
  }
  double v = 0.0;
  if (n != 0) {
    if (scale < -22 || scale > 22) return std::nullopt;
    v = scale < 0 ? static_cast<double>(n) / kPow10[-scale] : static_cast<double>(n) * kPow10[scale];
  }
  return negative ? -v : v;
}

double read_back(const Decimal& d, bool negative) {
  std::string text = negative ? "-" : "";
  text += d.digits.substr(0, 1) + "." + d.digits.substr(1) + "e" + std::to_string(d.exponent);
  return std::strtod(text.c_str(), nullptr);
}

/// `d` moved by one unit in its last digit (step +1 or -1), same digit count.
Decimal neighbour(Decimal d, int step) {
  std::string& s = d.digits;
  int i = static_cast<int>(s.size()) - 1;
  if (step > 0) {
    while (i >= 0 && s[static_cast<std::size_t>(i)] == '9') s[static_cast<std::size_t>(i--)] = '0';
    if (i < 0) {
      s.insert(s.begin(), '1');
      s.pop_back();
      ++d.exponent;
    } else {
      ++s[static_cast<std::size_t>(i)];
    }
  } else {
    while (i >= 0 && s[static_cast<std::size_t>(i)] == '0') s[static_cast<std::size_t>(i--)] = '9';
    if (i < 0) return {}; // below zero: no such neighbour
    --s[static_cast<std::size_t>(i)];
    if (s[0] == '0') { // 1000 -> 0999: one digit fewer above, so 9999 one decade down
      s.erase(s.begin());
      s.push_back('9');
      --d.exponent;
    }
  }
  return d;
}

/// The shortest digits that read back to |v| (finite, nonzero): for each count, the
/// nearest such decimal (%.*e rounds correctly); at a power of two, where the
/// values that read back reach further on one side, a neighbour may read back when
/// the nearest does not.
/// The decimal of `count` digits that reads back to v (negative: its sign), if any.
bool digits_of_count(double v, bool negative, int count, Decimal& out) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", count - 1, std::fabs(v));
  Decimal d;
  const char* e = std::strchr(buf, 'e');
  for (const char* c = buf; c < e; ++c) {
    if (*c != '.') d.digits.push_back(*c);
  }
  d.exponent = std::atoi(e + 1);
  if (read_back(d, negative) == v) return out = d, true;
  for (int step : {-1, 1}) {
    const Decimal n = neighbour(d, step);
    if (!n.digits.empty() && read_back(n, negative) == v) return out = n, true;
  }
  return false;
}

Decimal shortest_digits(double v) {
  const bool negative = std::signbit(v);
  Decimal d;
  // Most numbers a run writes need 16 or 17 digits. A decimal of fewer than 15
  // digits that reads back is, padded with zeros, one of 15 digits that does; and
  // 15-digit decimals lie further apart than the values that read back to v span,
  // so such a one is the nearest or its neighbour. No 15: start at 16 (the same
  // answer, two tries instead of sixteen; printf and strtod are slow in WebAssembly).
  const int first = digits_of_count(v, negative, 15, d) ? 1 : 16;
  for (int count = first; count <= 17; ++count) {
    if (digits_of_count(v, negative, count, d)) return d;
  }
  return d; // unreachable: 17 digits always read back
}

} // namespace

std::string printf_shortest(double v) {
  if (std::isnan(v)) return std::signbit(v) ? "-nan" : "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  const std::string sign = std::signbit(v) ? "-" : "";
  if (v == 0.0) return sign + "0";
  Decimal d;
  if (!short_decimal_digits(std::fabs(v), d)) d = shortest_digits(v);
  while (d.digits.size() > 1 && d.digits.back() == '0') d.digits.pop_back();
  const int count = static_cast<int>(d.digits.size());
  const int e = d.exponent;

  std::string scientific = d.digits.substr(0, 1);
  if (count > 1) scientific += "." + d.digits.substr(1);
  const std::string exponent_digits = std::to_string(std::abs(e)); // as printf's "e%+03d"
  scientific += (e < 0 ? "e-" : "e+") + std::string(exponent_digits.size() < 2 ? 1 : 0, '0') + exponent_digits;

  std::string fixed;
  if (e >= count - 1) {
    // An integer: to_chars writes it as %.0f does, all its digits exact (the same
    // length as the shortest digits padded with zeros, which decide the choice).
    if (std::fabs(v) < 9007199254740992.0) { // 2^53: the integer is its shortest digits
      fixed = d.digits + std::string(static_cast<std::size_t>(e - (count - 1)), '0');
    } else {
      char whole[400];
      std::snprintf(whole, sizeof whole, "%.0f", std::fabs(v));
      fixed = whole;
    }
  } else if (e >= 0) {
    fixed = d.digits.substr(0, static_cast<std::size_t>(e + 1)) + "." + d.digits.substr(static_cast<std::size_t>(e + 1));
  } else {
    fixed = "0." + std::string(static_cast<std::size_t>(-e - 1), '0') + d.digits;
  }
  return sign + (scientific.size() < fixed.size() ? scientific : fixed);
}

std::optional<double> strtod_strict(std::string_view text) {
  // from_chars' general syntax: -? (digits (. digits*)? | . digits) ([eE] [+-]? digits)?
  std::size_t i = 0;
  const auto digits_from = [&](std::size_t at) {
    std::size_t j = at;
    while (j < text.size() && text[j] >= '0' && text[j] <= '9') ++j;
    return j;
  };
  if (i < text.size() && text[i] == '-') ++i;
  const std::size_t int_end = digits_from(i);
  bool any_digit = int_end > i;
  bool nonzero = text.substr(i, int_end - i).find_first_not_of('0') != std::string_view::npos;
  i = int_end;
  if (i < text.size() && text[i] == '.') {
    const std::size_t frac_end = digits_from(i + 1);
    any_digit = any_digit || frac_end > i + 1;
    nonzero = nonzero || text.substr(i + 1, frac_end - i - 1).find_first_not_of('0') != std::string_view::npos;
    i = frac_end;
  }
  if (!any_digit) return std::nullopt;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < text.size() && (text[j] == '+' || text[j] == '-')) ++j;
    const std::size_t exp_end = digits_from(j);
    if (exp_end == j) return std::nullopt; // "1e": from_chars stops before the 'e'
    i = exp_end;
  }
  if (i != text.size()) return std::nullopt;
  if (const std::optional<double> quick = short_decimal_value(text)) return quick;
  const std::string copy(text);
  errno = 0;
  const double v = std::strtod(copy.c_str(), nullptr);
  if (!std::isfinite(v)) return std::nullopt;
  if (v == 0.0 && nonzero) return std::nullopt; // underflow: from_chars says out of range
  return v;
}

} // namespace soda
