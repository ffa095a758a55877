// InputError: the one exception type for bad input files.
//
// Its message is complete and ready for a user: where (file:line:column, or a JSON
// pointer), what (element and attribute), expected and got. Callers print what()
// and exit non-zero; nothing in the engine aborts on bad input.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace soda {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Location of a byte offset in a text: 1-based line and column (column counts
/// bytes, tabs as one).
struct TextLocation {
  long line = 1;
  long column = 1;
};

/// Where each line of a text starts, found once, so that a reader that names the
/// position of every element of a large file (a saved generation of thousands of
/// creatures) pays a binary search per position, not a scan from the start of the
/// file. Lines end at LF, CR LF or a lone CR (XML's end-of-line rule), so a position
/// is reported as an editor shows it whatever the file's line endings.
class LineIndex {
 public:
  explicit LineIndex(std::string_view text = {});
  /// Location of a byte offset, clamped to [0, size of the text].
  [[nodiscard]] TextLocation locate(std::ptrdiff_t offset) const;
  /// Byte offset of the first byte of 1-based line `line` (as locate numbers them).
  [[nodiscard]] std::size_t line_start(long line) const { return starts_[static_cast<std::size_t>(line - 1)]; }

 private:
  std::vector<std::size_t> starts_; ///< offset of each line's first byte
  std::size_t size_ = 0;
};

/// Location of one byte offset in a text (LineIndex's rule; scans the text once).
TextLocation locate_offset(const std::string& text, std::ptrdiff_t offset);

} // namespace soda
