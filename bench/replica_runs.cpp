#include "bench/replica_runs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/divergence.hpp"
#include "core/step_failure.hpp"

namespace sodaevo::bench {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

} // namespace

RunResult run_with_checkpoints(const soda::Model& model, const soda::Stepping& stepping,
                               const std::vector<long long>& checkpoints, const soda::SineJitter& jitter) {
  RunResult r;
  soda::State s = soda::make_state(model);
  s.jitter = jitter;
  soda::FrameStepper stepper(model, stepping, checkpoints.empty() ? 0 : checkpoints.back(), true);
  const std::size_t width = 2 * static_cast<std::size_t>(model.mass_count);
  long long done = 0;
  const auto t0 = Clock::now();
  for (long long frame : checkpoints) {
    if (!r.diverged) {
      try {
        stepper.run(s, frame - done);
        done = frame;
        r.diverged = soda::first_non_finite_mass(model, s) >= 0;
      } catch (const soda::StepFailure&) { // an implicit solve failed: the run counts as diverged
        r.diverged = true;
      }
    }
    if (r.diverged) {
      r.positions.emplace_back(width, kNaN);
      continue;
    }
    std::vector<double> p;
    p.reserve(width);
    for (int i = 0; i < model.mass_count; ++i) {
      p.push_back(s.x[i]);
      p.push_back(s.y[i]);
    }
    r.positions.push_back(std::move(p));
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

double centroid_x(const std::vector<double>& p) {
  double sx = 0.0;
  for (std::size_t i = 0; i < p.size(); i += 2) sx += p[i];
  return p.empty() ? 0.0 : sx / static_cast<double>(p.size() / 2);
}

ExpectedDistance expected_distance(const soda::Model& model, const soda::Stepping& stepping, const ReplicaPlan& plan) {
  ExpectedDistance e;
  std::vector<double> finite;
  double fastest = std::numeric_limits<double>::infinity();
  for (int r = 0; r < plan.replicas; ++r) {
    const RunResult run =
        run_with_checkpoints(model, stepping, plan.checkpoints, {static_cast<std::uint64_t>(r), plan.jitter});
    fastest = std::min(fastest, run.seconds);
    const double d = centroid_x(run.positions[plan.to]) - centroid_x(run.positions[plan.from]);
    e.distances.push_back(run.diverged ? kNaN : d);
    if (run.diverged) {
      ++e.diverged;
    } else {
      finite.push_back(d);
    }
    if (r == 0) {
      e.exact = e.distances.back();
      e.exact_positions = run.positions[plan.keep];
    }
  }
  if (!finite.empty()) {
    e.summary = summarize_sample(finite);
    e.standard_error = e.summary.sd / std::sqrt(static_cast<double>(e.summary.n));
  } else {
    e.summary.mean = kNaN;
    e.standard_error = kNaN;
  }
  e.seconds_per_frame = fastest / static_cast<double>(plan.checkpoints.back());
  return e;
}

DifferenceInterval difference_interval(const ExpectedDistance& a, const ExpectedDistance& b) {
  DifferenceInterval d;
  d.difference = a.summary.mean - b.summary.mean;
  if (a.summary.n == 0 || b.summary.n == 0) return {kNaN, kNaN, kNaN};
  const double va = a.standard_error * a.standard_error, vb = b.standard_error * b.standard_error;
  const double se = std::sqrt(va + vb);
  double half = 0.0;
  if (se > 0.0) {
    // Welch-Satterthwaite; a sample of one has no spread known (its variance 0 adds nothing).
    const double denominator = (a.summary.n > 1 ? va * va / (a.summary.n - 1) : 0.0) +
                               (b.summary.n > 1 ? vb * vb / (b.summary.n - 1) : 0.0);
    const double df = denominator > 0.0 ? (va + vb) * (va + vb) / denominator : 1.0;
    half = student_t_975(std::max(1, static_cast<int>(std::floor(df)))) * se;
  }
  d.low = d.difference - half;
  d.high = d.difference + half;
  return d;
}

} // namespace sodaevo::bench
