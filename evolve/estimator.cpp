#include "estimator.hpp"

#include <exception>

#include "evolve/replica_estimator.hpp"
#include "evolve/wire_format.hpp"

namespace sodaevo {

std::vector<Evaluation> SingleRollout::estimate(const Problem& problem,
                                                const std::vector<const soda::ModelDef*>& creatures) const {
  std::vector<Evaluation> results(creatures.size());
  std::vector<soda::ModelDef> prepared;
  prepared.reserve(creatures.size());
  std::vector<std::size_t> index; // result index of prepared[k]
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    try {
      prepared.push_back(problem.prepare(*creatures[i]));
      index.push_back(i);
    } catch (const std::exception& ex) {
      results[i].reason = ex.what();
    }
  }
  std::vector<const soda::ModelDef*> ptrs;
  for (const soda::ModelDef& p : prepared) ptrs.push_back(&p);
  std::vector<Evaluation> scored;
  try {
    scored = problem.rollouts(ptrs);
  } catch (const std::exception& ex) {
    for (std::size_t k = 0; k < prepared.size(); ++k) results[index[k]].reason = ex.what();
    return results;
  }
  for (std::size_t k = 0; k < prepared.size(); ++k) {
    Evaluation& e = results[index[k]];
    e = std::move(scored[k]);
    if (e.ok()) e.estimate = {1, e.fitness, 0.0, e.fitness};
  }
  return results;
}

void SingleRollout::write(WireWriter& out) const { out.text(kind()); }

std::unique_ptr<Estimator> read_estimator(WireReader& in) {
  const std::string kind = in.text();
  if (kind == "single") return std::make_unique<SingleRollout>();
  if (kind == "replicas") return std::make_unique<ReplicaEstimator>(ReplicaEstimator::read_fields(in));
  throw WireError("unknown estimator kind '" + kind + "'");
}

} // namespace sodaevo
