// bench transfer: do exported champions walk as claimed? (issue: fitness as a
// measured estimate)
//
// For each config and seed, a run with one rollout per creature (K = 1, today's
// GA before replicas) and a run with K replicas at an equal budget of simulated
// frames (the K = 1 run gets K times the generations). Each run's top creatures
// are checked on fresh replicas (evolve/runs/replica_check.hpp): the claim against
// the check is the winner's curse, the checked mean the creature's real
// ability. A separate, larger held-out ensemble then tells how often one more run
// (what the original program does) falls inside the check's 95 % prediction
// interval.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "evolve/config/run_config.hpp"

namespace sodaevo::bench {

struct TransferConfig {
  std::string name;  ///< e.g. "quick"
  RunConfig config;  ///< as read; seeds, replicas and generations are set per run
};

struct TransferOptions {
  std::vector<TransferConfig> configs;
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  std::vector<int> replica_counts{1, 8}; ///< the largest keeps the config's generations
  int top = 10;
  int check_replicas = 16;
  int holdout_replicas = 64;
  int threads = 0;
  std::filesystem::path work_dir; ///< run folders (replaced)
  std::function<void(const std::string&)> progress;
};

struct TransferRow {
  std::string config;
  std::uint64_t seed = 0;
  int replicas = 0;        ///< K of the run
  int generations = 0;
  int rank = 0;
  std::string id;
  int claim_n = 0;         ///< replicas behind the claim (survivors gather more)
  double claim = 0.0;      ///< the run's estimate (selection mean), px
  double exact = 0.0;      ///< replica 0, the exact engine, px
  double check_mean = 0.0, check_median = 0.0, check_sd = 0.0, check_lo = 0.0, check_hi = 0.0;
  double curse = 0.0;      ///< claim - check mean, px
  int holdout_n = 0;
  int holdout_inside = 0;  ///< held-out runs inside [check_lo, check_hi]
};

struct TransferSummary {
  std::string config;
  int replicas = 0;
  int champions = 0;
  double mean_curse_percent = 0.0;   ///< mean over champions of curse / check mean
  double pooled_curse_percent = 0.0; ///< sum of curses / sum of check means
  double median_curse_percent = 0.0; ///< median over champions of curse / check mean
  int near_zero = 0;                 ///< champions whose check mean is within one check sd of 0
  double mean_checked = 0.0;         ///< mean checked distance (real ability), px
  double coverage = 0.0;             ///< held-out runs inside the interval, share
};

struct TransferResult {
  std::vector<TransferRow> rows;
  std::vector<TransferSummary> summaries; ///< per config and K, then "all" per K
  double frames_per_run_k1 = 0.0;         ///< simulated frames of one K = 1 run (budget check)
};

TransferResult run_transfer_bench(const TransferOptions& options);

std::string transfer_csv(const TransferResult& result);
std::string transfer_markdown(const TransferResult& result, const TransferOptions& options, const std::string& command);
std::string transfer_svg(const TransferResult& result);

} // namespace sodaevo::bench
