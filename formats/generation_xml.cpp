#include "formats/generation_xml.hpp"

#include <sstream>

#include <pugixml.hpp>

#include "core/input_error.hpp"

namespace soda {

const std::string* SavedModelElement::find(std::string_view name) const {
  for (const auto& [key, value] : attributes) {
    if (key == name) return &value;
  }
  return nullptr;
}

std::string SavedModelElement::value(std::string_view name) const {
  const std::string* found = find(name);
  return found ? *found : std::string();
}

struct GenerationXml::Parsed {
  std::string text; // kept: positions look back at the byte before an element's name
  std::string source;
  pugi::xml_document doc;
  pugi::xml_node root;
  LineIndex lines;

  [[nodiscard]] std::string where(pugi::xml_node node) const {
    std::ptrdiff_t offset = node.offset_debug(); // the name, just after '<'
    if (offset > 0 && text[static_cast<std::size_t>(offset - 1)] == '<') --offset;
    const TextLocation at = lines.locate(offset);
    return source + ":" + std::to_string(at.line) + ":" + std::to_string(at.column);
  }
};

GenerationXml::GenerationXml(std::string_view text, const std::string& source) : parsed_(std::make_unique<Parsed>()) {
  Parsed& p = *parsed_;
  p.text = std::string(text);
  p.source = source;
  const pugi::xml_parse_result result = p.doc.load_buffer(p.text.data(), p.text.size());
  if (!result) {
    const TextLocation at = locate_offset(p.text, result.offset);
    throw InputError(source + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                     ": not a saved generation: XML syntax error: " + result.description());
  }
  p.root = p.doc.child("generation");
  if (!p.root) throw InputError(source + ": expected a <generation> root element");
  p.lines = LineIndex(p.text); // every creature's position is named: no scan per creature
}

GenerationXml::~GenerationXml() = default;

std::string GenerationXml::where() const { return parsed_->where(parsed_->root); }

std::string GenerationXml::index_text() const { return parsed_->root.attribute("index").value(); }

std::string GenerationXml::root_attribute(const char* name) const { return parsed_->root.attribute(name).value(); }

void GenerationXml::for_each_model(const std::function<void(const SavedModelElement&)>& visit) const {
  for (pugi::xml_node m : parsed_->root.children("model")) {
    SavedModelElement element;
    element.where = parsed_->where(m);
    for (pugi::xml_attribute a : m.attributes()) element.attributes.emplace_back(a.name(), a.value());
    std::ostringstream xml;
    m.print(xml, "\t", pugi::format_raw);
    element.xml = xml.str();
    visit(element);
  }
}

} // namespace soda
