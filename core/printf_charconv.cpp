#include "printf_charconv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace soda {

namespace {

/// A decimal d1.d2d3... x 10^exponent, digits without sign or point.
struct Decimal {
  std::string digits;
  int exponent = 0;
};

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
  Decimal d = shortest_digits(v);
  while (d.digits.size() > 1 && d.digits.back() == '0') d.digits.pop_back();
  const int count = static_cast<int>(d.digits.size());
  const int e = d.exponent;

  std::string scientific = d.digits.substr(0, 1);
  if (count > 1) scientific += "." + d.digits.substr(1);
  char exponent[16];
  std::snprintf(exponent, sizeof exponent, "e%c%02d", e < 0 ? '-' : '+', std::abs(e));
  scientific += exponent;

  std::string fixed;
  if (e >= count - 1) {
    // An integer: to_chars writes it as %.0f does, all its digits exact (the same
    // length as the shortest digits padded with zeros, which decide the choice).
    char whole[400];
    std::snprintf(whole, sizeof whole, "%.0f", std::fabs(v));
    fixed = whole;
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
  const std::string copy(text);
  errno = 0;
  const double v = std::strtod(copy.c_str(), nullptr);
  if (!std::isfinite(v)) return std::nullopt;
  if (v == 0.0 && nonzero) return std::nullopt; // underflow: from_chars says out of range
  return v;
}

} // namespace soda
