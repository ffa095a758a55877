#include "estimator.hpp"


#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

std::vector<Evaluation> SingleRollout::estimate(const Problem& problem,
                                                const std::vector<const soda::ModelDef*>& creatures) const {
  // One exact replica: the replica estimator's replica 0 alone.
  ReplicaPlan one;
  one.replicas = 1;
  one.replicas_max = 1;
  return ReplicaEstimator(one).estimate(problem, creatures);
}

void SingleRollout::write(WireWriter& out) const { out.text(kind()); }

std::unique_ptr<Estimator> read_estimator(WireReader& in) {
  const std::string kind = in.text();
  if (kind == "single") return std::make_unique<SingleRollout>();
  if (kind == "replicas") return std::make_unique<ReplicaEstimator>(ReplicaEstimator::read_fields(in));
  throw WireError("unknown estimator kind '" + kind + "'");
}

} // namespace sodaevo
