#include "evolve/estimators/replica_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "core/mix64.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

namespace {

/// The mean of each descriptor over runs[first, first + count), summed in replica
/// order (empty unless every run has the same number of them).
std::vector<double> mean_descriptors(const std::vector<Evaluation>& runs, std::size_t first, std::size_t count) {
  std::vector<double> mean(runs[first].descriptors.size(), 0.0);
  for (std::size_t r = first; r < first + count; ++r) {
    if (runs[r].descriptors.size() != mean.size()) return {};
    for (std::size_t d = 0; d < mean.size(); ++d) mean[d] += runs[r].descriptors[d];
  }
  for (double& m : mean) m /= static_cast<double>(count);
  return mean;
}

} // namespace

std::uint64_t creature_key(const soda::ModelDef& creature) {
  soda::ModelDef genome = creature;
  genome.name.clear();
  genome.comment.clear();
  const std::vector<char> bytes = encode_creature(genome);
  std::uint64_t h = 0x6a09e667f3bcc909ULL;
  for (char c : bytes) h = soda::mix64(h ^ static_cast<unsigned char>(c));
  return soda::mix64(h ^ bytes.size());
}

std::uint64_t replica_seed(std::uint64_t run_seed, ReplicaPurpose purpose, std::uint64_t key, int replica) {
  if (purpose == ReplicaPurpose::Selection && replica == 0) return 0;
  std::uint64_t h = soda::mix64(run_seed ^ 0x243f6a8885a308d3ULL);
  h = soda::mix64(h ^ static_cast<std::uint64_t>(purpose));
  h = soda::mix64(h ^ key);
  h = soda::mix64(h ^ static_cast<std::uint64_t>(replica));
  return h == 0 ? 1 : h;
}

ReplicaPlan replica_plan(const FitnessConfig& fitness, std::uint64_t run_seed) {
  ReplicaPlan p;
  p.replicas = fitness.replicas;
  p.replicas_max = fitness.replicas_max;
  p.statistic = fitness.statistic;
  p.jitter = fitness.jitter;
  p.run_seed = run_seed;
  return p;
}

double replica_statistic(const std::vector<double>& scores, EstimateStatistic statistic) {
  const SampleSummary s = summarize_sample(scores);
  switch (statistic) {
    case EstimateStatistic::Mean: return s.mean;
    case EstimateStatistic::Median: return s.median;
    case EstimateStatistic::LowerBound:
      if (s.n < 2) return s.mean;
      return s.mean - student_t_975(s.n - 1) * s.sd / std::sqrt(static_cast<double>(s.n));
  }
  return s.mean;
}

ReplicaEstimator::ReplicaEstimator(ReplicaPlan plan) : plan_(plan) {}

std::vector<Evaluation> ReplicaEstimator::estimate(const Problem& problem,
                                                   const std::vector<const soda::ModelDef*>& creatures) const {
  const int k = plan_.replicas;
  std::vector<Evaluation> results(creatures.size());
  std::vector<soda::ModelDef> prepared;
  prepared.reserve(creatures.size()); // no reallocation: the rollouts point into it
  std::vector<std::size_t> index;     // result index of prepared[j]
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    try {
      prepared.push_back(problem.prepare(*creatures[i]));
      index.push_back(i);
    } catch (const std::exception& ex) {
      results[i].reason = ex.what();
    }
  }
  std::vector<Rollout> runs;
  runs.reserve(prepared.size() * static_cast<std::size_t>(k));
  for (std::size_t j = 0; j < prepared.size(); ++j) {
    const std::uint64_t key = creature_key(*creatures[index[j]]);
    for (int r = plan_.first_replica; r < plan_.first_replica + k; ++r) {
      runs.emplace_back(&prepared[j], soda::SineJitter{replica_seed(plan_.run_seed, ReplicaPurpose::Selection, key, r),
                                                       plan_.jitter});
    }
  }
  std::vector<Evaluation> scored;
  try {
    scored = problem.rollouts(runs);
  } catch (const std::exception& ex) {
    for (std::size_t j = 0; j < prepared.size(); ++j) results[index[j]].reason = ex.what();
    return results;
  }
  for (std::size_t j = 0; j < prepared.size(); ++j) {
    Evaluation& e = results[index[j]];
    const std::size_t first = j * static_cast<std::size_t>(k);
    std::vector<double> scores;
    for (int r = 0; r < k; ++r) {
      const Evaluation& run = scored[first + static_cast<std::size_t>(r)];
      if (!run.ok()) {
        e = run;
        if (k > 1 || plan_.first_replica > 0) {
          e.reason = "replica " + std::to_string(plan_.first_replica + r) + " of " +
                     std::to_string(plan_.first_replica + k) + ": " + e.reason;
        }
        break;
      }
      scores.push_back(run.fitness);
    }
    if (static_cast<int>(scores.size()) < k) continue;
    e = scored[first]; // replica 0: the exact run's distance
    const SampleSummary s = summarize_sample(scores);
    e.fitness = replica_statistic(scores, plan_.statistic);
    e.estimate = {s.n, s.mean, s.sd, s.median};
    e.descriptors = mean_descriptors(scored, first, static_cast<std::size_t>(k));
  }
  return results;
}

int ReplicaEstimator::resample_to(const Evaluation& kept) const {
  if (!kept.ok() || kept.estimate.rollouts <= 0 || kept.estimate.rollouts >= plan_.replicas_max) return 0;
  return std::min(kept.estimate.rollouts + plan_.replicas, plan_.replicas_max);
}

int ReplicaEstimator::confirm_to(const Evaluation& kept) const {
  if (!kept.ok() || kept.estimate.rollouts <= 0 || kept.estimate.rollouts >= plan_.replicas_max) return 0;
  return plan_.replicas_max;
}

std::unique_ptr<Estimator> ReplicaEstimator::with_rollouts(int rollouts) const {
  ReplicaPlan p = plan_;
  p.replicas = rollouts;
  p.replicas_max = std::max(p.replicas_max, rollouts);
  return std::make_unique<ReplicaEstimator>(p);
}

ReplicaEstimator ReplicaEstimator::on_replicas(int first, int count) const {
  ReplicaPlan p = plan_;
  p.first_replica = first;
  p.replicas = count;
  p.replicas_max = std::max(p.replicas_max, count);
  return ReplicaEstimator(p);
}

void ReplicaEstimator::write(WireWriter& out) const {
  out.text(kind());
  out.i32(plan_.replicas);
  out.i32(plan_.first_replica);
  out.i32(plan_.replicas_max);
  out.u8(static_cast<std::uint8_t>(plan_.statistic));
  out.f64(plan_.jitter);
  out.u64(plan_.run_seed);
}

ReplicaEstimator ReplicaEstimator::read_fields(WireReader& in) {
  ReplicaPlan p;
  p.replicas = in.i32();
  p.first_replica = in.i32();
  p.replicas_max = in.i32();
  const int statistic = in.u8();
  p.jitter = in.f64();
  p.run_seed = in.u64();
  if (p.replicas < 1 || p.first_replica < 0 || p.replicas_max < p.replicas || statistic > 2 || !(p.jitter >= 0.0 && p.jitter <= 1.0)) {
    throw WireError("replica estimator: bad settings");
  }
  p.statistic = static_cast<EstimateStatistic>(statistic);
  return ReplicaEstimator(p);
}

} // namespace sodaevo
