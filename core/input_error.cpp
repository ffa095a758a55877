#include "input_error.hpp"

#include <algorithm>

namespace soda {

// Lines end at LF, CR LF or a lone CR (XML's end-of-line rule), so a position is
// reported the way an editor shows it whatever the file's line endings.
TextLocation locate_offset(const std::string& text, std::ptrdiff_t offset) {
  const std::size_t end = offset <= 0 ? 0 : std::min(static_cast<std::size_t>(offset), text.size());
  TextLocation loc;
  for (std::size_t i = 0; i < end; ++i) {
    const char c = text[i];
    if (c == '\n' || (c == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) {
      ++loc.line;
      loc.column = 1;
    } else {
      ++loc.column; // the CR of a CR LF pair is a byte of the line like any other
    }
  }
  return loc;
}

} // namespace soda
