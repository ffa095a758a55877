// The XML escape of every file we write that declares ISO-8859-1 (model files,
// saved generations): one place, so that no writer forgets to transcode.
#pragma once

#include <string>
#include <string_view>

namespace soda {

/// Appends UTF-8 text escaped for an ISO-8859-1 XML document: markup characters as
/// entities, U+00A0..U+00FF as single latin-1 bytes, the C1 controls and
/// everything above U+00FF as character references. Characters XML 1.0 does not
/// allow (and malformed UTF-8) become U+FFFD. In attribute values, tab, LF and CR
/// are written as references too, since a parser would turn them into spaces.
void append_xml_escaped(std::string& out, std::string_view utf8, bool attribute);

/// append_xml_escaped for an attribute value, as a string.
std::string xml_attribute_escaped(std::string_view utf8);

} // namespace soda
