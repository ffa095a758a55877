// InputError: the one exception type for bad input files.
//
// Its message is complete and ready for a user: where (file:line:column, or a JSON
// pointer), what (element and attribute), expected and got. Callers print what()
// and exit non-zero; nothing in the engine aborts on bad input.
#pragma once

#include <stdexcept>
#include <string>

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

TextLocation locate_offset(const std::string& text, std::ptrdiff_t offset);

} // namespace soda
