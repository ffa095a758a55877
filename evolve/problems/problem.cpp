#include "problem.hpp"

#include "evolve/problems/race_problem.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

std::unique_ptr<Problem> read_problem(WireReader& in) {
  const std::string kind = in.text();
  if (kind == "walk") return std::make_unique<WalkProblem>(WalkProblem::read_fields(in));
  if (kind == "race") return std::make_unique<RaceProblem>(RaceProblem::read_fields(in));
  throw WireError("unknown problem kind '" + kind + "'");
}

} // namespace sodaevo
