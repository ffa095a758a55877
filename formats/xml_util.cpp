#include "formats/xml_util.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>

#include "core/number_text.hpp"

namespace soda::xml {

namespace {

constexpr char32_t kReplacement = 0xFFFD;
constexpr char32_t kInvalid = 0xFFFFFFFF;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string upper_ascii(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  }
  return out;
}

/// Decodes one UTF-8 sequence at s[i], advancing i past it (or past one byte if it
/// is malformed, returning kInvalid). Overlong forms and surrogates are malformed.
char32_t decode_one(std::string_view s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) {
    ++i;
    return b0;
  }
  std::size_t len = 0;
  char32_t cp = 0;
  unsigned char lo = 0x80, hi = 0xBF; // allowed range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    len = 2;
    cp = b0 & 0x1F;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    len = 3;
    cp = b0 & 0x0F;
    if (b0 == 0xE0) lo = 0xA0;
    if (b0 == 0xED) hi = 0x9F; // no surrogates
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    len = 4;
    cp = b0 & 0x07;
    if (b0 == 0xF0) lo = 0x90;
    if (b0 == 0xF4) hi = 0x8F;
  } else {
    ++i;
    return kInvalid;
  }
  if (i + len > s.size()) {
    ++i;
    return kInvalid;
  }
  for (std::size_t k = 1; k < len; ++k) {
    const unsigned char b = byte(i + k);
    const unsigned char min = k == 1 ? lo : 0x80;
    const unsigned char max = k == 1 ? hi : 0xBF;
    if (b < min || b > max) {
      ++i;
      return kInvalid;
    }
    cp = (cp << 6) | (b & 0x3F);
  }
  i += len;
  return cp;
}

/// The value of the encoding pseudo-attribute of an XML declaration at the start
/// of `text`, or nullopt if there is no declaration or it names no encoding.
std::optional<std::string> declared_encoding(std::string_view text) {
  if (text.substr(0, 5) != "<?xml" || text.size() < 6 || !is_space(text[5])) return std::nullopt;
  const std::size_t end = text.find("?>");
  if (end == std::string_view::npos) return std::nullopt; // pugixml reports it
  const std::string_view decl = text.substr(0, end);
  std::size_t pos = decl.find("encoding");
  while (pos != std::string_view::npos) {
    std::size_t i = pos + 8;
    if (pos > 0 && is_space(decl[pos - 1])) {
      while (i < decl.size() && is_space(decl[i])) ++i;
      if (i < decl.size() && decl[i] == '=') {
        ++i;
        while (i < decl.size() && is_space(decl[i])) ++i;
        if (i < decl.size() && (decl[i] == '"' || decl[i] == '\'')) {
          const std::size_t close = decl.find(decl[i], i + 1);
          if (close != std::string_view::npos) return std::string(decl.substr(i + 1, close - i - 1));
        }
      }
    }
    pos = decl.find("encoding", pos + 1);
  }
  return std::nullopt;
}

bool is_latin1_name(const std::string& upper) {
  static const char* const names[] = {"ISO-8859-1", "ISO8859-1", "ISO_8859-1", "ISO_8859-1:1987",
                                      "LATIN1",     "LATIN-1",   "L1",         "ISO-IR-100",
                                      "CP819",      "IBM819",    "CSISOLATIN1"};
  return std::any_of(std::begin(names), std::end(names), [&](const char* n) { return upper == n; });
}

bool is_utf8_name(const std::string& upper) {
  return upper == "UTF-8" || upper == "UTF8" || upper == "US-ASCII" || upper == "ASCII";
}

std::string hex_byte(unsigned char b) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", b);
  return buf;
}

std::string code_point_text(char32_t cp) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(cp));
  return buf;
}

} // namespace

// --- SourceText ------------------------------------------------------------------

SourceText::SourceText(std::string_view raw, std::string source_name) : name_(std::move(source_name)) {
  const auto starts_with = [&](std::initializer_list<unsigned char> bytes) {
    if (raw.size() < bytes.size()) return false;
    std::size_t k = 0;
    for (unsigned char b : bytes) {
      if (static_cast<unsigned char>(raw[k++]) != b) return false;
    }
    return true;
  };
  bool bom = false;
  if (starts_with({0xEF, 0xBB, 0xBF})) {
    raw.remove_prefix(3);
    bom = true;
  } else if (starts_with({0xFE, 0xFF}) || starts_with({0xFF, 0xFE}) || starts_with({0x00, 0x3C}) ||
             starts_with({0x3C, 0x00}) || starts_with({0x00, 0x00})) {
    throw InputError(name_ +
                     ":1:1: the file is in UTF-16 or UTF-32, which is not supported: "
                     "expected UTF-8 or ISO-8859-1 (as SodaConstructor writes)");
  }

  if (!bom) {
    if (std::optional<std::string> enc = declared_encoding(raw)) {
      const std::string upper = upper_ascii(*enc);
      if (is_latin1_name(upper)) {
        from_latin1_ = true;
      } else if (!is_utf8_name(upper)) {
        throw InputError(name_ +
                         ":1:1: XML declaration attribute 'encoding': expected UTF-8 or "
                         "ISO-8859-1, got " +
                         quote(*enc));
      }
    }
  }

  if (from_latin1_) {
    utf8_.reserve(raw.size() + raw.size() / 8);
    for (char c : raw) append_utf8(utf8_, static_cast<unsigned char>(c));
  } else {
    utf8_.assign(raw);
  }

  lines_ = LineIndex(utf8_);

  for (std::size_t i = 0; i < utf8_.size();) {
    const std::size_t at = i;
    const unsigned char b = static_cast<unsigned char>(utf8_[i]);
    const char32_t cp = decode_one(utf8_, i);
    if (cp == kInvalid) {
      throw InputError(where(static_cast<std::ptrdiff_t>(at)) + ": invalid UTF-8 byte " + hex_byte(b) +
                       ": expected UTF-8 text (a file without an XML declaration is UTF-8; a latin-1 "
                       "file must start with <?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>)");
    }
    if (!is_xml_char(cp)) {
      throw InputError(where(static_cast<std::ptrdiff_t>(at)) + ": character " + code_point_text(cp) +
                       " is not allowed in an XML document: expected text, got a control "
                       "character (is this a binary file?)");
    }
  }
}

TextLocation SourceText::locate(std::ptrdiff_t utf8_offset) const {
  TextLocation loc = lines_.locate(utf8_offset);
  if (from_latin1_) {
    // One column per character: count the bytes that start a UTF-8 sequence.
    const std::size_t start = lines_.line_start(loc.line);
    const std::size_t off = start + static_cast<std::size_t>(loc.column - 1);
    loc.column = 1;
    for (std::size_t i = start; i < off; ++i) {
      if ((static_cast<unsigned char>(utf8_[i]) & 0xC0) != 0x80) ++loc.column;
    }
  }
  return loc;
}

std::string SourceText::where(std::ptrdiff_t utf8_offset) const {
  const TextLocation loc = locate(utf8_offset);
  return name_ + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column);
}

void SourceText::parse(pugi::xml_document& doc) const {
  // parse_ws_pcdata_single keeps a comment made only of white space.
  const pugi::xml_parse_result result = doc.load_buffer(
      utf8_.data(), utf8_.size(), pugi::parse_default | pugi::parse_ws_pcdata_single, pugi::encoding_utf8);
  if (!result) {
    throw InputError(where(result.offset) + ": XML syntax error: " + result.description());
  }
  // pugixml walks the tree without recursion, so this check costs no stack.
  struct DepthCheck : pugi::xml_tree_walker {
    pugi::xml_node too_deep;
    bool for_each(pugi::xml_node& node) override {
      if (node.type() != pugi::node_element || depth() < kMaxXmlDepth) return true;
      too_deep = node;
      return false;
    }
  } check;
  doc.traverse(check);
  if (check.too_deep) {
    std::ptrdiff_t off = check.too_deep.offset_debug();
    if (off > 0 && utf8_[static_cast<std::size_t>(off - 1)] == '<') --off;
    throw InputError(where(off) + ": <" + check.too_deep.name() + ">: expected elements nested at most " +
                     std::to_string(kMaxXmlDepth) + " levels deep (a limit of this program; a model has fewer than 10), got deeper");
  }
}

// --- ReadContext -----------------------------------------------------------------

std::ptrdiff_t ReadContext::element_offset(pugi::xml_node node) const {
  std::ptrdiff_t off = node.offset_debug(); // the element's name, just after '<'
  if (off < 0) return 0;
  if (off > 0 && source_.utf8()[static_cast<std::size_t>(off - 1)] == '<') --off;
  return off;
}

std::ptrdiff_t ReadContext::attribute_offset(pugi::xml_node node, const char* attribute) const {
  const std::string& text = source_.utf8();
  const std::ptrdiff_t name_off = node.offset_debug();
  if (name_off < 0) return element_offset(node);
  const std::string_view attr(attribute);
  std::size_t i = static_cast<std::size_t>(name_off);
  while (i < text.size() && !is_space(text[i]) && text[i] != '>' && text[i] != '/') ++i; // the name
  while (i < text.size() && text[i] != '>') {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      const std::size_t close = text.find(c, i + 1);
      if (close == std::string::npos) break;
      i = close + 1;
      continue;
    }
    if (is_space(text[i - 1]) && text.compare(i, attr.size(), attr) == 0) {
      std::size_t k = i + attr.size();
      while (k < text.size() && is_space(text[k])) ++k;
      if (k < text.size() && text[k] == '=') return static_cast<std::ptrdiff_t>(i);
    }
    ++i;
  }
  return element_offset(node);
}

std::string ReadContext::where(pugi::xml_node node, const char* attribute) const {
  return source_.where(attribute != nullptr ? attribute_offset(node, attribute) : element_offset(node));
}

std::string ReadContext::describe(pugi::xml_node node, const char* attribute) const {
  std::string out = "<";
  out += node.name();
  const std::string_view tag = node.name();
  const char* key = nullptr;
  if (tag == "field") {
    key = "name";
  } else if (tag == "object" || tag == "mass" || tag == "node") {
    key = "id";
  }
  if (key != nullptr) {
    if (pugi::xml_attribute a = node.attribute(key)) {
      out += ' ';
      out += key;
      out += "=\"";
      out += a.value();
      out += '"';
    }
  }
  out += '>';
  if (attribute != nullptr) {
    out += " attribute '";
    out += attribute;
    out += '\'';
  }
  return out;
}

void ReadContext::fail(pugi::xml_node node, const char* attribute, std::string_view message) const {
  throw InputError(where(node, attribute) + ": " + describe(node, attribute) + ": " + std::string(message));
}

void ReadContext::warn(pugi::xml_node node, const char* attribute, std::string_view message) {
  if (warnings_.size() >= kMaxWarnings) {
    ++dropped_warnings_;
    return;
  }
  warnings_.push_back(where(node, attribute) + ": " + describe(node, attribute) + ": " +
                      std::string(message));
}

void ReadContext::finish() {
  if (dropped_warnings_ > 0) {
    warnings_.push_back(source_.name() + ": " + std::to_string(dropped_warnings_) +
                        " more warnings not shown");
    dropped_warnings_ = 0;
  }
}

// --- text --------------------------------------------------------------------------

std::string quote(std::string_view value) {
  constexpr std::size_t kMaxShown = 80;
  std::size_t shown = value.size();
  if (shown > kMaxShown) {
    shown = kMaxShown;
    while (shown > 0 && (static_cast<unsigned char>(value[shown]) & 0xC0) == 0x80) --shown;
  }
  std::string out = "'";
  for (std::size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(value[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c < 0x20 || c == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (shown < value.size()) out += "...";
  out += '\'';
  return out;
}

std::string range_text(Range range) {
  // Appended piece by piece: "[" + std::string&& trips GCC 12's -Wrestrict false positive.
  std::string out = "[";
  out += format_double_plain(range.min);
  out += ", ";
  out += format_double_plain(range.max);
  out += ']';
  return out;
}

bool is_xml_char(char32_t cp) {
  return cp == 0x9 || cp == 0xA || cp == 0xD || (cp >= 0x20 && cp <= 0xD7FF) ||
         (cp >= 0xE000 && cp <= 0xFFFD) || (cp >= 0x10000 && cp <= 0x10FFFF);
}

std::u32string decode_xml_text(std::string_view utf8, bool& changed) {
  changed = false;
  std::u32string out;
  out.reserve(utf8.size());
  for (std::size_t i = 0; i < utf8.size();) {
    char32_t cp = decode_one(utf8, i);
    if (cp == kInvalid || !is_xml_char(cp)) {
      cp = kReplacement;
      changed = true;
    }
    out.push_back(cp);
  }
  return out;
}

void append_utf8(std::string& out, char32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

std::string element_text(ReadContext& ctx, pugi::xml_node element) {
  std::string raw;
  for (pugi::xml_node child : element.children()) {
    if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata) {
      raw += child.value();
    } else if (child.type() == pugi::node_element) {
      ctx.warn(child, nullptr, std::string("element inside <") + element.name() + "> ignored");
    }
  }
  bool changed = false;
  const std::u32string cps = decode_xml_text(raw, changed);
  if (!changed) return raw;
  ctx.warn(element, nullptr,
           "characters XML 1.0 does not allow (from character references) were replaced by U+FFFD");
  std::string out;
  for (char32_t cp : cps) append_utf8(out, cp);
  return out;
}

} // namespace soda::xml
