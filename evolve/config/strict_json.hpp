// Strict JSON reading for the run config: the text parsed with every problem
// named where it is (file:line:column for syntax, a JSON pointer for a duplicate
// key), and the small pieces of text a message about a JSON value needs.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sodaevo {

/// One problem found while reading: where, and "expected ..., got ..." or similar.
struct ConfigProblem {
  std::string pointer;
  std::string message;
};

/// Parses `text`. A syntax error, a number too large for a double, or nesting
/// deeper than kMaxJsonDepth throws soda::InputError naming `source` and the
/// line and column (or the pointer); each duplicate key goes to `duplicate` with
/// its pointer and parsing goes on (nlohmann would keep the last one silently).
nlohmann::json parse_strict_json(const std::string& text, const std::string& source,
                                 const std::function<void(const std::string& pointer)>& duplicate);

/// RFC 6901 escaping of one reference token.
std::string escape_token(const std::string& key);

/// A pointer as a message shows it ("(top level)" for the root).
std::string show_pointer(const std::string& pointer);

/// A JSON value as it appears in a message (long values shortened).
std::string show_json(const nlohmann::json& value);

/// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b);

} // namespace sodaevo
