// Internal helpers of the model file layer (model_file.hpp): the source text of a
// model file made ready for pugixml, positions and messages, and XML character
// rules shared by the readers and the writer. Not part of the public interface.
//
// Encoding: SodaConstructor 1.x files declare ISO-8859-1; v2 files have no
// declaration (so UTF-8). SourceText converts latin-1 to UTF-8 itself, rather than
// letting pugixml do it, so that every offset pugixml reports can be turned back
// into the line and column of the file as it is on disk.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "core/constants.hpp"
#include "core/input_error.hpp"
#include "core/model_def.hpp"

namespace soda::xml {

/// The bytes of a model file as UTF-8 text, with a way back to file positions.
class SourceText {
 public:
  /// Identifies the encoding (UTF-8 BOM, XML declaration; default UTF-8), converts
  /// latin-1 to UTF-8, and checks the result holds only characters XML 1.0 allows
  /// (valid UTF-8, no control characters but tab, LF, CR). Throws InputError.
  SourceText(std::string_view raw, std::string source_name);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& utf8() const { return utf8_; }

  /// Line and column in the file on disk of a byte offset into utf8(). Columns
  /// count bytes of the file (so one per character of a latin-1 file).
  [[nodiscard]] TextLocation locate(std::ptrdiff_t utf8_offset) const;
  /// "file:line:column" of a byte offset into utf8().
  [[nodiscard]] std::string where(std::ptrdiff_t utf8_offset) const;

  /// Parses utf8() into `doc`. A syntax error becomes an InputError with the file
  /// position and pugixml's description.
  void parse(pugi::xml_document& doc) const;

 private:
  std::string name_;
  std::string utf8_;
  bool from_latin1_ = false;
  LineIndex lines_; // of utf8_
};

/// State shared by the readers while they walk one document: positions, messages,
/// warnings.
class ReadContext {
 public:
  ReadContext(const SourceText& source, std::vector<std::string>& warnings)
      : source_(source), warnings_(warnings) {}

  /// "file:line:column" of an element (its '<'), or of one of its attributes when
  /// `attribute` is given and present in the start tag.
  [[nodiscard]] std::string where(pugi::xml_node node, const char* attribute = nullptr) const;

  /// "file:line:col: <element ...> [attribute 'x']: " + message, thrown as InputError.
  [[noreturn]] void fail(pugi::xml_node node, const char* attribute, std::string_view message) const;
  /// The same text, recorded as a warning.
  void warn(pugi::xml_node node, const char* attribute, std::string_view message);
  /// Appends a summary if warnings were dropped (at most kMaxWarnings are kept, so
  /// a huge generated file cannot flood the output).
  void finish();

  static constexpr std::size_t kMaxWarnings = 100;

 private:
  [[nodiscard]] std::string describe(pugi::xml_node node, const char* attribute) const;
  [[nodiscard]] std::ptrdiff_t element_offset(pugi::xml_node node) const;
  [[nodiscard]] std::ptrdiff_t attribute_offset(pugi::xml_node node, const char* attribute) const;

  const SourceText& source_;
  std::vector<std::string>& warnings_;
  std::size_t dropped_warnings_ = 0;
};

/// A value as it is shown in a message: single-quoted, control characters escaped,
/// cut after 80 bytes.
std::string quote(std::string_view value);

/// "[min, max]" with the numbers in shortest form.
std::string range_text(Range range);

/// Whether XML 1.0 allows the code point in a document (Char production).
bool is_xml_char(char32_t cp);

/// Decodes UTF-8 text into code points. Malformed sequences, surrogates and code
/// points XML 1.0 forbids become U+FFFD; `changed` tells whether that happened.
std::u32string decode_xml_text(std::string_view utf8, bool& changed);

/// Appends the UTF-8 encoding of a code point.
void append_utf8(std::string& out, char32_t cp);

/// Text of an element's character data (text and CDATA children), made safe by
/// decode_xml_text (a warning is recorded if anything was replaced). Child
/// elements are ignored with a warning.
std::string element_text(ReadContext& ctx, pugi::xml_node element);

// --- the two readers (xml_v1_reader.cpp, xml_v2_reader.cpp) ----------------------

/// Reads a v1 `<model>` element (docs/file-formats.md, v1) into `def`.
void read_v1_model(ReadContext& ctx, pugi::xml_node model, ModelDef& def);

/// Reads a v2 object graph whose root `<object>` is given (docs/file-formats.md, v2) into
/// `def`.
void read_v2_model(ReadContext& ctx, pugi::xml_node root, ModelDef& def);

} // namespace soda::xml
