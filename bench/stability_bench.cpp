#include "stability_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "bench/extreme_creatures.hpp"
#include "core/divergence.hpp"
#include "core/model.hpp"
#include "core/stability.hpp"
#include "core/step_failure.hpp"
#include "evolve/evaluators/parallel_for.hpp"
#include "evolve/algorithms/rng.hpp"

namespace sodaevo::bench {

namespace {

StabilityCase run_case(long long index, const StabilityBenchOptions& o) {
  Rng rng = Rng::stream(o.seed, static_cast<std::uint64_t>(index), 0, 0x57e55);
  const soda::Model model = soda::build_model(extreme_creature(rng));
  StabilityCase c;
  c.creature = index;
  c.masses = model.mass_count;
  soda::State state = soda::make_state(model);
  c.margin_first = soda::predict_stability(model, state, o.stepping).margin;
  c.margin_min = c.margin_first;
  soda::FrameStepper stepper(model, o.stepping, o.frames);
  soda::DivergenceMonitor monitor(model, state, {}, true);
  for (long long f = 1; f <= o.frames; ++f) {
    try {
      stepper.step(state);
    } catch (const soda::StepFailure& failure) {
      c.diverged = true;
      c.diverged_frame = failure.frame;
      c.reason = failure.reason;
      return c;
    }
    if (!monitor.check(state)) {
      c.diverged = true;
      c.diverged_frame = monitor.result().frame;
      c.reason = monitor.result().reason;
      return c;
    }
    if (f % o.sample_every == 0 && f < o.frames) {
      c.margin_min = std::min(c.margin_min, soda::predict_stability(model, state, o.stepping).margin);
    }
  }
  const double limit = 0.99 * 20.0 * (1.0 - model.friction);
  for (int i = 0; i < model.mass_count; ++i) {
    if (std::hypot(state.vx[i], state.vy[i]) >= limit && limit > 0.0) c.speed_limited = true;
    if (state.x[i] <= 0.0 || state.x[i] >= model.width || state.y[i] <= 0.0 || state.y[i] >= model.height) {
      c.touching = true;
    }
  }
  return c;
}

} // namespace

Confusion confusion(const std::vector<double>& margins, const std::vector<bool>& diverged, double threshold) {
  Confusion c;
  for (std::size_t i = 0; i < margins.size(); ++i) {
    const bool predicted = margins[i] < threshold;
    if (predicted && diverged[i]) ++c.true_positive;
    else if (predicted) ++c.false_positive;
    else if (diverged[i]) ++c.false_negative;
    else ++c.true_negative;
  }
  return c;
}

std::vector<RocPoint> roc_curve(const std::vector<double>& margins, const std::vector<bool>& diverged) {
  std::vector<std::size_t> order(margins.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return margins[a] < margins[b]; });
  const auto positives = static_cast<double>(std::count(diverged.begin(), diverged.end(), true));
  const double negatives = static_cast<double>(diverged.size()) - positives;
  std::vector<RocPoint> roc = {{-std::numeric_limits<double>::infinity(), 0.0, 0.0}};
  double tp = 0.0, fp = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    (diverged[order[k]] ? tp : fp) += 1.0;
    // One point per distinct margin: tied creatures enter together.
    if (k + 1 < order.size() && margins[order[k + 1]] == margins[order[k]]) continue;
    const double threshold = k + 1 < order.size() ? margins[order[k + 1]] : std::numeric_limits<double>::infinity();
    roc.push_back({threshold, negatives > 0 ? fp / negatives : 0.0, positives > 0 ? tp / positives : 0.0});
  }
  return roc;
}

double roc_area(const std::vector<double>& margins, const std::vector<bool>& diverged) {
  std::vector<std::size_t> order(margins.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return margins[a] < margins[b]; });
  const auto healthy_total = static_cast<double>(std::count(diverged.begin(), diverged.end(), false));
  const double diverged_total = static_cast<double>(diverged.size()) - healthy_total;
  // Over groups of equal margin, ascending: a diverged creature beats every healthy
  // one above its group and half of those in it.
  double wins = 0.0, healthy_below = 0.0;
  for (std::size_t k = 0; k < order.size();) {
    double d = 0.0, h = 0.0;
    std::size_t end = k;
    for (; end < order.size() && margins[order[end]] == margins[order[k]]; ++end) (diverged[order[end]] ? d : h) += 1.0;
    wins += d * (healthy_total - healthy_below - h) + 0.5 * d * h;
    healthy_below += h;
    k = end;
  }
  const double pairs = healthy_total * diverged_total;
  return pairs > 0 ? wins / pairs : 0.0;
}

StabilityBenchReport run_stability_bench(const StabilityBenchOptions& o) {
  StabilityBenchReport r;
  r.cases.resize(static_cast<std::size_t>(o.creatures));
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for_index(static_cast<std::size_t>(o.creatures), o.threads,
                     [&](std::size_t i) { r.cases[i] = run_case(static_cast<long long>(i), o); });
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<double> first, lowest;
  std::vector<bool> diverged;
  for (const StabilityCase& c : r.cases) {
    first.push_back(c.margin_first);
    lowest.push_back(c.margin_min);
    diverged.push_back(c.diverged);
  }
  r.first = confusion(first, diverged, 1.0);
  r.lowest = confusion(lowest, diverged, 1.0);
  r.roc_first = roc_curve(first, diverged);
  r.roc_lowest = roc_curve(lowest, diverged);
  r.auc_first = roc_area(first, diverged);
  r.auc_lowest = roc_area(lowest, diverged);
  return r;
}

} // namespace sodaevo::bench
