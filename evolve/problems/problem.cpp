#include "problem.hpp"

#include <optional>

#include "evolve/problems/race_problem.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

std::unique_ptr<Problem> read_problem(WireReader& in) {
  const std::string tag = in.text();
  const std::optional<FitnessKind> kind = parse_fitness_kind(tag);
  if (!kind) throw WireError("unknown problem kind '" + tag + "'");
  switch (*kind) {
    case FitnessKind::Walk: return std::make_unique<WalkProblem>(WalkProblem::read_fields(in));
    case FitnessKind::Race: return std::make_unique<RaceProblem>(RaceProblem::read_fields(in));
  }
  throw WireError("unknown problem kind '" + tag + "'");
}

} // namespace sodaevo
