// Numbers as text: strict parsing and shortest round-trip formatting.
//
// Files are the interface between runs, programs and people, so every double that
// is written reads back to the same bits (std::to_chars shortest form) and parsing
// rejects anything that is not entirely a finite number (std::from_chars; the XML
// parser's own conversions accept trailing junk and depend on the locale).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace soda {

/// Shortest text that reads back to exactly `v` (finite v). Integral values get a
/// ".0" suffix, as Java writes them ("55.0"), so written files look like real
/// SodaConstructor files; the value is unchanged.
std::string format_double(double v);

/// Shortest round-trip text without the ".0" suffix (CSV and JSON output).
std::string format_double_plain(double v);

/// `v` formatted by a printf conversion for one double ("%.2f", "%+.0f px"): the
/// text of tables, charts and pictures, where a rounded number is wanted.
std::string format_printf(const char* format, double v);

/// Parses a whole string as a finite double. Leading/trailing ASCII white space is
/// allowed (XML attributes often carry it); a leading '+' is accepted as Java does.
/// Returns nullopt for empty text, junk, trailing characters, inf, nan or overflow.
std::optional<double> parse_double(std::string_view text);

/// Parses a whole string as an int (base 10, optional sign, surrounding white
/// space allowed). nullopt on junk or overflow.
std::optional<long long> parse_integer(std::string_view text);

} // namespace soda
