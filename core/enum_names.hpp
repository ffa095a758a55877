// EnumName: the one table that spells an enum's values, as MuJoCo keeps one
// schema behind every name map. The config reader, the command line, the page and
// the Python module read and write names through these tables only, so a value
// added to an enum and to its table is accepted everywhere at once, and one added
// to the enum alone is named nowhere (name_of gives "?", which the config's
// round-trip test rejects) instead of being refused by one reader and not another.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace soda {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value` in `table`, "?" when the table lacks it.
template <class E, std::size_t N>
std::string name_of(const EnumName<E> (&table)[N], E value) {
  for (const EnumName<E>& n : table) {
    if (n.value == value) return n.name;
  }
  return "?";
}

/// The value named `name`, nullopt for a name the table does not hold.
template <class E, std::size_t N>
std::optional<E> value_of(const EnumName<E> (&table)[N], std::string_view name) {
  for (const EnumName<E>& n : table) {
    if (name == n.name) return n.value;
  }
  return std::nullopt;
}

/// Every name, in the table's order (for messages and option lists).
template <class E, std::size_t N>
std::vector<std::string> names_of(const EnumName<E> (&table)[N]) {
  std::vector<std::string> out;
  for (const EnumName<E>& n : table) out.emplace_back(n.name);
  return out;
}

} // namespace soda
