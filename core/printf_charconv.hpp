// Shortest round-trip double text and strict double parsing from printf and strtod.
//
// number_text.cpp uses std::to_chars / std::from_chars for doubles. The C++ library
// of Debian's Emscripten (3.1.6, the WebAssembly build of web/) has them deleted, so
// that build uses these instead. They give the same text and the same results: the
// digits are found by printf's correctly rounded %.*e (the shortest count that reads
// back, the nearest such digits), laid out as to_chars lays them out (fixed or
// scientific, whichever is shorter, fixed on a tie); parsing checks from_chars'
// syntax by hand and converts with the correctly rounded strtod. Native builds
// compile them too, so the tests hold them against the standard functions.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace soda {

/// The text std::to_chars(first, last, v) writes for a double (shortest round
/// trip, "inf", "-inf", "nan" for the others).
std::string printf_shortest(double v);

/// What std::from_chars reads from the whole of `text` (no white space, no '+'):
/// nullopt where from_chars stops early or reports an error (overflow, or a nonzero
/// number that rounds to zero); "inf" and "nan" are refused (callers want finite
/// numbers only).
std::optional<double> strtod_strict(std::string_view text);

} // namespace soda
