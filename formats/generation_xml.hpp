// The XML of a saved generation (the run folder's generations/gen_NNNNN.xml and a
// checkpoint's population): a <generation index="..."> root holding one <model>
// element per creature, a v1 model with the GA's attributes (id, parents, status,
// fitness, ...). This layer knows the XML but not the GA: it hands each <model>
// element over with its attributes, position and text, and evolve/store/run_store.cpp
// checks the values. Writing is plain text (run_store.cpp's generation_to_xml).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace soda {

/// One <model> element of a saved generation.
struct SavedModelElement {
  std::string where;                                           ///< "source:line:column" of its '<'
  std::vector<std::pair<std::string, std::string>> attributes; ///< as written, in order
  std::string xml;                                             ///< the element alone, for read_model_text

  /// The first attribute of that name, or nullptr if there is none.
  [[nodiscard]] const std::string* find(std::string_view name) const;
  /// The first attribute of that name, or "" if there is none.
  [[nodiscard]] std::string value(std::string_view name) const;
};

/// A saved generation, parsed. Throws InputError on construction for an XML syntax
/// error (naming source:line:column) or a root other than <generation>.
class GenerationXml {
 public:
  GenerationXml(std::string_view text, const std::string& source);
  ~GenerationXml();
  GenerationXml(const GenerationXml&) = delete;
  GenerationXml& operator=(const GenerationXml&) = delete;

  /// "source:line:column" of the <generation> element.
  [[nodiscard]] std::string where() const;
  /// The root's index attribute as written ("" if absent).
  [[nodiscard]] std::string index_text() const;
  /// The root's attribute `name` as written ("" if absent).
  [[nodiscard]] std::string root_attribute(const char* name) const;
  /// Calls `visit` on every <model> child of the root, in document order (an
  /// exception from `visit` ends the walk).
  void for_each_model(const std::function<void(const SavedModelElement&)>& visit) const;

 private:
  struct Parsed;
  std::unique_ptr<Parsed> parsed_;
};

} // namespace soda
