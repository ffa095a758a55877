#include "input_error.hpp"

#include <algorithm>

namespace soda {

LineIndex::LineIndex(std::string_view text) : size_(text.size()) {
  starts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    // The CR of a CR LF pair is a byte of its line like any other.
    if (c == '\n' || (c == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) starts_.push_back(i + 1);
  }
}

TextLocation LineIndex::locate(std::ptrdiff_t offset) const {
  const std::size_t off = offset <= 0 ? 0 : std::min(static_cast<std::size_t>(offset), size_);
  // The last line starting at or before off.
  const auto line = std::upper_bound(starts_.begin(), starts_.end(), off) - starts_.begin();
  return TextLocation{static_cast<long>(line), static_cast<long>(off - starts_[static_cast<std::size_t>(line - 1)]) + 1};
}

TextLocation locate_offset(const std::string& text, std::ptrdiff_t offset) { return LineIndex(text).locate(offset); }

} // namespace soda
