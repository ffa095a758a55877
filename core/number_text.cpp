#include "number_text.hpp"

#include <cstdio>

#include <charconv>
#include <cmath>
#include <system_error>

#include "printf_charconv.hpp"

// Debian's Emscripten (the WebAssembly build, web/) has no floating-point
// to_chars/from_chars; printf_charconv.hpp gives the same results there.
#if defined(__EMSCRIPTEN__)
#define SODA_FLOAT_CHARCONV 0
#else
#define SODA_FLOAT_CHARCONV 1
#endif

namespace soda {

namespace {

std::string_view trim(std::string_view s) {
  auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

} // namespace

std::string format_double_plain(double v) {
#if !SODA_FLOAT_CHARCONV
  return printf_shortest(v);
#else
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec; // 64 bytes always suffice for a double
  return std::string(buf, end);
#endif
}

std::string format_double(double v) {
  std::string s = format_double_plain(v);
  if (std::isfinite(v) && s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

std::optional<double> parse_double(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
#if !SODA_FLOAT_CHARCONV
  return strtod_strict(text);
#else
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
#endif
}

std::optional<long long> parse_integer(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
  long long v = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

std::string format_printf(const char* format, double v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

} // namespace soda
