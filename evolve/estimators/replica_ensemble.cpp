#include "replica_ensemble.hpp"
#include "core/cancellation.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/divergence.hpp"

namespace sodaevo {
namespace {

/// Whether some free mass of `b` is more than the tolerance away from `a`'s.
bool parted(const soda::Model& model, const soda::State& a, const soda::State& b) {
  for (int i = 0; i < model.mass_count; ++i) {
    // Written so that a NaN counts as parted.
    if (!(std::fabs(a.x[i] - b.x[i]) <= kHorizonTolerance && std::fabs(a.y[i] - b.y[i]) <= kHorizonTolerance)) {
      return true;
    }
  }
  return false;
}

} // namespace

std::vector<std::uint64_t> consecutive_seeds(int count) {
  std::vector<std::uint64_t> seeds;
  for (int r = 0; r < count; ++r) seeds.push_back(static_cast<std::uint64_t>(r));
  return seeds;
}

ReplicaResults run_replicas(const soda::Model& model, const ReplicaSettings& settings) {
  if (settings.seeds.empty()) throw std::invalid_argument("run_replicas: no replicas");
  if (settings.settle < 0 || settings.frames < 0) throw std::invalid_argument("run_replicas: negative frame count");
  const long long total = settings.settle + settings.frames;
  std::vector<soda::State> states;
  for (std::uint64_t seed : settings.seeds) {
    states.push_back(soda::make_state(model));
    states.back().jitter = {seed, settings.probability};
    soda::require_valid_jitter(states.back().jitter, "run_replicas");
  }
  soda::FrameStepper stepper(model, settings.stepping, total, /*reference_step=*/true);
  const std::size_t count = states.size();
  std::vector<double> start_x(count, 0.0);
  ReplicaResults out;
  for (long long frame = 0;; ++frame) {
    if (frame == settings.settle) {
      for (std::size_t r = 0; r < count; ++r) start_x[r] = soda::mass_centroid(model, states[r]).x;
    }
    if (out.horizon < 0) {
      for (std::size_t r = 1; r < count && out.horizon < 0; ++r) {
        if (parted(model, states[0], states[r])) out.horizon = frame;
      }
    }
    if (frame == total) break;
    if (frame % soda::kCancellationFrames == soda::kCancellationFrames - 1) soda::check_cancellation();
    for (soda::State& s : states) stepper.step(s);
  }
  for (std::size_t r = 0; r < count; ++r) {
    const bool finite = !soda::first_non_finite(model, states[r]);
    out.distances.push_back(finite ? soda::mass_centroid(model, states[r]).x - start_x[r]
                                   : std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

} // namespace sodaevo
