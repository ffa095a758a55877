// Fitness kinds: what a Problem scores, each named once with how its scores read.
//
// A Problem says its kind (Problem::fitness_kind); whatever shows a score (the
// command line, run reports, champions.json, the page) reads the kind's row here
// instead of asking "is this a race?", so a new kind is labelled by its own row,
// never as another's. A walk's fitness is px walked (more is better); a race's is
// minus its frames to the finish, shown as frames (fewer is better).
// docs/ARCHITECTURE.md lists the files a new kind touches.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sodaevo {

/// /fitness/kind: what a creature is scored on.
enum class FitnessKind { Walk, Race };

struct FitnessKindInfo {
  FitnessKind kind;
  const char* name;         ///< /fitness/kind and the Problem's wire tag
  const char* unit;         ///< of a score as shown, of Evaluation::distance and of checks
  const char* fitness_unit; ///< of a raw fitness column
  const char* score_name;   ///< what a shown score is called in tables and captions
  bool lower_is_better;     ///< fitness = minus the shown score
  int digits;               ///< decimals of a shown score in one-line summaries

  /// A fitness as it is shown: px, or a race's frames.
  [[nodiscard]] double shown(double fitness) const { return lower_is_better ? -fitness : fitness; }
};

inline constexpr FitnessKindInfo kFitnessKinds[] = {
    {FitnessKind::Walk, "walk", "px", "px", "fitness", false, 2},
    {FitnessKind::Race, "race", "frames", "-frames", "race result", true, 1},
};

/// The row of `kind` (std::logic_error if the table lacks it: a kind added to the
/// enum alone fails every test that scores it).
const FitnessKindInfo& fitness_kind_info(FitnessKind kind);
std::string fitness_kind_name(FitnessKind kind); ///< "walk", "race"
std::optional<FitnessKind> parse_fitness_kind(std::string_view name);
std::vector<std::string> fitness_kind_names();

} // namespace sodaevo
