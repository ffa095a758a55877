#include "bench/transfer_bench.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/evaluators/parallel_for.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/estimators/sample_summary.hpp"

namespace sodaevo::bench {

namespace fs = std::filesystem;
using charts::fixed;

namespace {

/// The run of `base` with `replicas` per creature at the budget of simulated
/// frames that the largest K gets with the config's generations.
RunConfig transfer_run_config(const RunConfig& base, std::uint64_t seed, int replicas, int largest) {
  RunConfig c = base;
  c.seed = seed;
  c.fitness.replicas = replicas;
  c.fitness.replicas_max = replicas == 1 ? 1 : std::max(32, replicas);
  c.budget.generations = base.budget.generations * std::max(1, largest / replicas);
  c.save.generation_every = 0; // the last only: the top creatures
  c.save.checkpoint_every = c.budget.generations;
  return c;
}

/// How many of `runs` fall inside [lo, hi].
int inside(const std::vector<double>& runs, double lo, double hi) {
  return static_cast<int>(std::count_if(runs.begin(), runs.end(), [&](double d) { return d >= lo && d <= hi; }));
}

/// The held-out runs of `individual`: seeds of their own purpose, never seen by
/// selection nor by the check.
std::vector<double> holdout_distances(const Problem& problem, const Individual& individual, const sodaevo::ReplicaPlan& plan,
                                      int count) {
  const soda::ModelDef prepared = problem.prepare(individual.creature);
  const std::uint64_t key = creature_key(individual.creature);
  std::vector<Rollout> runs;
  for (int r = 0; r < count; ++r) {
    runs.emplace_back(&prepared, soda::SineJitter{replica_seed(plan.run_seed, ReplicaPurpose::HeldOut, key, r), plan.jitter});
  }
  std::vector<double> d;
  for (const Evaluation& e : problem.rollouts(runs)) {
    if (e.ok()) d.push_back(e.distance);
  }
  return d;
}

TransferSummary summarize(const std::vector<const TransferRow*>& rows, const std::string& config, int k) {
  TransferSummary s;
  s.config = config;
  s.replicas = k;
  double curse = 0.0, checked = 0.0;
  long long in = 0, total = 0;
  std::vector<double> ratios;
  for (const TransferRow* r : rows) {
    ++s.champions;
    ratios.push_back(100.0 * r->curse / std::fabs(r->check_mean));
    s.mean_curse_percent += ratios.back();
    if (std::fabs(r->check_mean) <= r->check_sd) ++s.near_zero;
    curse += r->curse;
    checked += std::fabs(r->check_mean);
    s.mean_checked += r->check_mean;
    in += r->holdout_inside;
    total += r->holdout_n;
  }
  if (s.champions > 0) {
    s.mean_curse_percent /= s.champions;
    s.mean_checked /= s.champions;
    s.pooled_curse_percent = checked > 0 ? 100.0 * curse / checked : 0.0;
    s.median_curse_percent = summarize_sample(ratios).median;
  }
  s.coverage = total > 0 ? static_cast<double>(in) / static_cast<double>(total) : 0.0;
  return s;
}

} // namespace

TransferResult run_transfer_bench(const TransferOptions& opt) {
  TransferResult result;
  const int largest = *std::max_element(opt.replica_counts.begin(), opt.replica_counts.end());
  for (const TransferConfig& tc : opt.configs) {
    for (const std::uint64_t seed : opt.seeds) {
      for (const int k : opt.replica_counts) {
        const RunConfig config = transfer_run_config(tc.config, seed, k, largest);
        if (k == 1) {
          result.frames_per_run_k1 = static_cast<double>(config.budget.generations) * config.population.size *
                                     static_cast<double>(config.fitness.frames + config.fitness.settle_frames);
        }
        const fs::path dir = opt.work_dir / (tc.name + "-seed" + std::to_string(seed) + "-k" + std::to_string(k));
        if (opt.progress) {
          opt.progress(tc.name + " seed " + std::to_string(seed) + ": K = " + std::to_string(k) + ", " +
                       std::to_string(config.budget.generations) + " generations");
        }
        {
          RunStore store = RunStore::create(dir, config, true, "bench transfer");
          ThreadEvaluator evaluator(opt.threads);
          run_evolution(store, evaluator, {});
        }
        const RunConfig saved = read_run_config(dir / "config.json");
        const RunRoles roles = roles_of(saved);
        const sodaevo::ReplicaPlan plan = replica_plan(saved);
        const std::vector<Individual> best = best_individuals(dir, opt.top);
        std::vector<TransferRow> rows(best.size());
        parallel_for_index(best.size(), opt.threads, [&](std::size_t i) {
          const ReplicaCheck c = check_on_fresh_replicas(*roles.problem, best[i], plan, opt.check_replicas);
          TransferRow& r = rows[i];
          r.config = tc.name;
          r.seed = seed;
          r.replicas = k;
          r.generations = config.budget.generations;
          r.rank = static_cast<int>(i + 1);
          r.id = best[i].id;
          if (!c.ok) return;
          r.claim_n = c.selection.rollouts;
          r.claim = c.selection.mean;
          r.exact = c.exact_distance;
          r.check_mean = c.check.mean;
          r.check_median = c.check.median;
          r.check_sd = c.check.sd;
          r.check_lo = c.check.interval95_low;
          r.check_hi = c.check.interval95_high;
          r.curse = c.winners_curse;
          const std::vector<double> held = holdout_distances(*roles.problem, best[i], plan, opt.holdout_replicas);
          r.holdout_n = static_cast<int>(held.size());
          r.holdout_inside = inside(held, r.check_lo, r.check_hi);
        });
        for (TransferRow& r : rows) {
          if (r.claim_n > 0) result.rows.push_back(std::move(r));
        }
      }
    }
  }
  std::vector<std::string> names;
  for (const TransferConfig& tc : opt.configs) names.push_back(tc.name);
  names.push_back("all");
  for (const std::string& name : names) {
    for (const int k : opt.replica_counts) {
      std::vector<const TransferRow*> rows;
      for (const TransferRow& r : result.rows) {
        if (r.replicas == k && (name == "all" || r.config == name)) rows.push_back(&r);
      }
      result.summaries.push_back(summarize(rows, name, k));
    }
  }
  return result;
}

std::string transfer_csv(const TransferResult& result) {
  std::ostringstream o;
  o.precision(17);
  o << "config,seed,replicas,generations,rank,id,claim_n,claim,exact,check_mean,check_median,check_sd,"
       "check_interval95_lo,check_interval95_hi,winners_curse,holdout_n,holdout_inside\n";
  for (const TransferRow& r : result.rows) {
    o << r.config << ',' << r.seed << ',' << r.replicas << ',' << r.generations << ',' << r.rank << ',' << r.id << ','
      << r.claim_n << ',' << r.claim << ',' << r.exact << ',' << r.check_mean << ',' << r.check_median << ','
      << r.check_sd << ',' << r.check_lo << ',' << r.check_hi << ',' << r.curse << ',' << r.holdout_n << ','
      << r.holdout_inside << '\n';
  }
  return o.str();
}

std::string transfer_markdown(const TransferResult& result, const TransferOptions& opt, const std::string& command) {
  std::ostringstream md;
  md << "Measured with `" << command << "`: " << opt.seeds.size() << " seeds per config, the top " << opt.top
     << " creatures of each run, each checked on " << opt.check_replicas
     << " fresh replicas (seeds selection never used) and judged by " << opt.holdout_replicas
     << " held-out runs. The K = 1 runs get K times the generations of the K runs, so both simulate about "
     << fixed(result.frames_per_run_k1 / 1e6, 1)
     << "M frames per run (plus the survivors' resampling and, with K replicas, the final confirmation of the best "
        "10 on /fitness/replicas_max replicas).\n\n";
  md << "| config | K | champions | winner's curse: mean of claim - check over mean check | mean of claim / check - 1 "
        "| median of claim / check - 1 | checks within 1 sd of 0 | checked distance (px, mean) "
        "| held-out runs inside the 95 % interval |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const TransferSummary& s : result.summaries) {
    md << "| " << s.config << " | " << s.replicas << " | " << s.champions << " | " << fixed(s.pooled_curse_percent, 2)
       << " % | " << fixed(s.mean_curse_percent, 2) << " % | " << fixed(s.median_curse_percent, 2) << " % | "
       << s.near_zero << " | " << fixed(s.mean_checked, 1) << " | " << fixed(100.0 * s.coverage, 1) << " % |\n";
  }
  md << "\nThe winner's curse is the claim (the estimate the run selected on) minus the mean of the fresh check. "
        "Its mean over the champions, relative to their mean checked distance, is the first column. The mean of "
        "each champion's ratio claim / check - 1 weighs a champion that walks a few px as much as one that walks "
        "thousands: where a check is within one sd of 0 its ratio is mostly noise of either sign (both the claim and "
        "the check are means of a few runs whose spread exceeds the distance), so that column is given but is not "
        "the measure. The checked distance is what the creatures really walk. The interval is the check's 95 % "
        "prediction interval for one more run, mean +- t(0.975, M-1) sd sqrt(1 + 1/M).\n";
  return md.str();
}

std::string transfer_svg(const TransferResult& result) {
  charts::BarChart chart;
  chart.title = "Winner's curse: claim against a check on fresh replicas (mean over champions)";
  chart.y_axis.label = "mean claim - check over mean check, %";
  charts::BarSeries curse;
  curse.name = "winner's curse, %";
  for (const TransferSummary& s : result.summaries) {
    chart.categories.push_back(s.config + ", K = " + std::to_string(s.replicas));
    curse.values.push_back(s.pooled_curse_percent);
  }
  chart.series.push_back(std::move(curse));
  return charts::render_bar_chart(chart);
}

} // namespace sodaevo::bench
