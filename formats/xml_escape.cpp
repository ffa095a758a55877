#include "formats/xml_escape.hpp"

#include "formats/xml_util.hpp"

namespace soda {

void append_xml_escaped(std::string& out, std::string_view utf8, bool attribute) {
  bool changed = false;
  for (char32_t cp : xml::decode_xml_text(utf8, changed)) {
    switch (cp) {
      case '&': out += "&amp;"; continue;
      case '<': out += "&lt;"; continue;
      case '>': out += "&gt;"; continue;
      case '"': out += "&quot;"; continue;
      case '\r': out += "&#13;"; continue; // a raw CR would be read back as LF
      case '\t':
      case '\n':
        if (!attribute) {
          out += static_cast<char>(cp);
          continue;
        }
        break;
      default:
        if ((cp >= 0x20 && cp < 0x7F) || (cp >= 0xA0 && cp <= 0xFF)) {
          out += static_cast<char>(static_cast<unsigned char>(cp));
          continue;
        }
        break;
    }
    out += "&#" + std::to_string(static_cast<unsigned long>(cp)) + ";";
  }
}

std::string xml_attribute_escaped(std::string_view utf8) {
  std::string out;
  append_xml_escaped(out, utf8, true);
  return out;
}

} // namespace soda
