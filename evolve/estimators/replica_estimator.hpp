// ReplicaEstimator: a creature's fitness as a measured estimate over replicas.
//
// Why: a walker is chaotic. This engine reproduces SodaConstructor on an x86-64
// JDK 9+ bit for bit (it computes that JVM's Math.sin), but on another machine's
// sine (an aarch64 JVM, JDK 8, another language's sin) a run parts from it at the
// first sine that differs in its last bit; from there it is another draw from the
// creature's distribution of distances. A GA that keeps the best single draw keeps the
// luckiest one (the winner's curse: exported champions claimed about 9 % more
// than they walked in the original). So every creature is run K times: replica 0
// exact, replicas 1.. with their own sine jitter (core/sine_jitter.hpp), which
// models another machine's sine; its fitness is a statistic of the K scores
// (mean, median, or the lower end of the 95 % confidence interval of the mean).
//
// Adaptive resampling: a creature that survives into the next generation (an
// elite) is estimated again on /fitness/replicas more replicas, up to
// /fitness/replicas_max, so the estimate of what is kept sharpens instead of
// keeping a lucky draw; new children start with K.
//
// Seeds: replica r of a creature has seed 0 (exact) for r = 0, else a nonzero hash
// of (run seed, purpose, the genome's bits, r). A pure function: the same on any
// thread or rank count, on resume and in replay; the replicas of a surviving
// creature extend its first ones. The purpose keeps the seeds of selection and
// of the check on fresh replicas (`export`) apart.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "evolve/estimators/estimator.hpp"
#include "evolve/problems/fitness_settings.hpp"

namespace sodaevo {

/// What a replica's seed is for: the estimate the GA selects on, a check on
/// replicas never used in selection, or a held-out ensemble that judges the check
/// (bench transfer).
enum class ReplicaPurpose : std::uint64_t { Selection = 1, Check = 2, HeldOut = 3 };

/// The genome's identity for seeds: a hash of its bits, name and comment left out.
std::uint64_t creature_key(const soda::ModelDef& creature);

/// Seed of replica `replica` (>= 0): 0 for replica 0 of the selection, else nonzero.
std::uint64_t replica_seed(std::uint64_t run_seed, ReplicaPurpose purpose, std::uint64_t creature_key,
                           int replica);

/// The estimator's settings (keys under /fitness, see configs/README.md).
struct ReplicaPlan {
  int replicas = 8;        ///< per new creature
  /// The first replica's index: an estimate is on replicas [first_replica,
  /// first_replica + replicas). MAP-Elites adds replicas to an estimate this way
  /// (evolve/algorithms/map_elites.hpp); 0 everywhere else.
  int first_replica = 0;
  int replicas_max = 32;   ///< cap of adaptive resampling
  EstimateStatistic statistic = EstimateStatistic::Mean;
  double jitter = 0.002;   ///< probability of a +-1 ulp sine in a jittered replica
  std::uint64_t run_seed = 1;

  bool operator==(const ReplicaPlan&) const = default;
};

/// The plan of /fitness (replicas, replicas_max, statistic, jitter) in a run of
/// seed `run_seed` (runs/run_roles.hpp: the plan of a run's config).
ReplicaPlan replica_plan(const FitnessConfig& fitness, std::uint64_t run_seed);

/// The statistic of replica scores (at least one): mean, median, or
/// mean - t(0.975, n-1) * sd / sqrt(n) (the mean itself for one score).
double replica_statistic(const std::vector<double>& scores, EstimateStatistic statistic);

class ReplicaEstimator final : public Estimator {
 public:
  explicit ReplicaEstimator(ReplicaPlan plan);

  [[nodiscard]] const ReplicaPlan& plan() const { return plan_; }
  [[nodiscard]] std::string kind() const override { return "replicas"; }
  /// plan.replicas rollouts of each creature (from replica plan.first_replica).
  /// Any replica that diverges makes the creature Diverged (the reason names the
  /// replica). Ok: fitness = the statistic of the replicas' fitness, estimate =
  /// their count, mean, sd and median, descriptors = their mean (when the Problem
  /// measures them); distance and px_per_frame are the first replica's (replica 0:
  /// the exact run, which `simulate` of the exported creature gives).
  [[nodiscard]] std::vector<Evaluation> estimate(const Problem& problem,
                                                 const std::vector<const soda::ModelDef*>& creatures) const override;
  [[nodiscard]] int resample_to(const Evaluation& kept) const override;
  /// replicas_max for a valid creature estimated on fewer, else 0.
  [[nodiscard]] int confirm_to(const Evaluation& kept) const override;
  [[nodiscard]] std::unique_ptr<Estimator> with_rollouts(int rollouts) const override;
  /// This estimator on replicas [first, first + count) (count >= 1).
  [[nodiscard]] ReplicaEstimator on_replicas(int first, int count) const;
  void write(WireWriter& out) const override;
  /// The fields `write` wrote after the kind tag.
  static ReplicaEstimator read_fields(WireReader& in);

 private:
  ReplicaPlan plan_;
};

} // namespace sodaevo
