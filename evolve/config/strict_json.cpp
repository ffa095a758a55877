#include "strict_json.hpp"

#include <algorithm>
#include <set>
#include <vector>

#include "core/input_error.hpp"
#include "evolve/config/input_limits.hpp"

namespace sodaevo {

using nlohmann::json;

namespace {

/// nlohmann's parse_error message without its "[json.exception...] parse error at
/// line L, column C: " prefix (we compute the location ourselves).
std::string strip_nlohmann_prefix(const std::string& what) {
  std::string s = what;
  if (s.rfind("[json.exception.", 0) == 0) {
    const std::size_t close = s.find("] ");
    if (close != std::string::npos) s = s.substr(close + 2);
  }
  const std::size_t column = s.find(", column ");
  if (s.rfind("parse error", 0) == 0 && column != std::string::npos) {
    const std::size_t colon = s.find(": ", column);
    if (colon != std::string::npos) s = s.substr(colon + 2);
  }
  return s;
}

/// Location text "line:column" of a byte offset; a UTF-8 byte order mark at the
/// start of the text is not counted as columns of line 1.
std::string location_text(const std::string& text, std::ptrdiff_t offset) {
  soda::TextLocation loc = soda::locate_offset(text, offset);
  if (loc.line == 1 && text.rfind("\xEF\xBB\xBF", 0) == 0) loc.column = std::max(1L, loc.column - 3);
  return std::to_string(loc.line) + ":" + std::to_string(loc.column);
}

/// Offset of a number token outside strings, or -1 (nlohmann reports a number too
/// large for a double without a position).
std::ptrdiff_t find_number_token(const std::string& text, const std::string& token) {
  if (token.empty()) return -1;
  auto in_number = [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-';
  };
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
      continue;
    }
    if (text.compare(i, token.size(), token) == 0 && (i == 0 || !in_number(text[i - 1])) &&
        (i + token.size() >= text.size() || !in_number(text[i + token.size()]))) {
      return static_cast<std::ptrdiff_t>(i);
    }
  }
  return -1;
}

} // namespace

std::string escape_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string show_pointer(const std::string& pointer) {
  return pointer.empty() ? "(top level)" : pointer;
}

std::string show_json(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  constexpr std::size_t kMax = 120;
  if (s.size() > kMax) s = s.substr(0, kMax) + "...";
  return s;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

json parse_strict_json(const std::string& text, const std::string& source,
                       const std::function<void(const std::string& pointer)>& duplicate) {
  struct Frame {
    bool is_object;
    std::set<std::string> keys;
    std::string token; ///< the member being parsed (key or element index)
    std::size_t elements = 0;
  };
  std::vector<Frame> stack;
  auto path_of = [&stack]() {
    std::string p;
    for (std::size_t i = 0; i + 1 < stack.size(); ++i) p += "/" + stack[i].token;
    return p;
  };
  auto begin_value = [&stack]() {
    if (!stack.empty() && !stack.back().is_object) {
      stack.back().token = std::to_string(stack.back().elements++);
    }
  };
  const json::parser_callback_t callback = [&](int depth, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        begin_value();
        if (depth >= kMaxJsonDepth) {
          // Deeper than any config could be: stop before it costs stack or memory.
          std::string p = path_of();
          if (!stack.empty()) p += "/" + stack.back().token;
          throw soda::InputError(source + ": " + show_pointer(p) + ": expected JSON nested at most " +
                                 std::to_string(kMaxJsonDepth) + " levels deep, got deeper");
        }
        stack.push_back(Frame{event == json::parse_event_t::object_start, {}, {}, 0});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack.empty()) stack.pop_back();
        break;
      case json::parse_event_t::key: {
        Frame& top = stack.back();
        const std::string key = parsed.get<std::string>();
        top.token = escape_token(key);
        if (!top.keys.insert(key).second) {
          std::string p = path_of();
          p += "/" + top.token;
          duplicate(p);
        }
        break;
      }
      case json::parse_event_t::value:
        begin_value();
        break;
    }
    return true;
  };
  try {
    return json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/false);
  } catch (const json::parse_error& e) {
    const auto offset = static_cast<std::ptrdiff_t>(e.byte) - 1;
    throw soda::InputError(source + ":" + location_text(text, offset) +
                           ": invalid JSON: " + strip_nlohmann_prefix(e.what()));
  } catch (const json::out_of_range& e) {
    // "number overflow parsing '1e400'": the only out_of_range the parser throws.
    const std::string what = e.what();
    const std::size_t q1 = what.find('\'');
    const std::size_t q2 = what.rfind('\'');
    const std::string token = (q1 != std::string::npos && q2 > q1) ? what.substr(q1 + 1, q2 - q1 - 1) : "";
    const std::ptrdiff_t at = find_number_token(text, token);
    const std::string where = at >= 0 ? source + ":" + location_text(text, at) : source;
    throw soda::InputError(where + ": invalid JSON: number " + token + " is too large");
  }
}

} // namespace sodaevo
