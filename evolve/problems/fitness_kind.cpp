#include "evolve/problems/fitness_kind.hpp"

#include <stdexcept>

namespace sodaevo {

const FitnessKindInfo& fitness_kind_info(FitnessKind kind) {
  for (const FitnessKindInfo& k : kFitnessKinds) {
    if (k.kind == kind) return k;
  }
  throw std::logic_error("fitness kind " + std::to_string(static_cast<int>(kind)) + " has no row in kFitnessKinds");
}

std::string fitness_kind_name(FitnessKind kind) { return fitness_kind_info(kind).name; }

std::optional<FitnessKind> parse_fitness_kind(std::string_view name) {
  for (const FitnessKindInfo& k : kFitnessKinds) {
    if (name == k.name) return k.kind;
  }
  return std::nullopt;
}

std::vector<std::string> fitness_kind_names() {
  std::vector<std::string> out;
  for (const FitnessKindInfo& k : kFitnessKinds) out.emplace_back(k.name);
  return out;
}

} // namespace sodaevo
