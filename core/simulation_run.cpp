#include "core/simulation_run.hpp"
#include "core/cancellation.hpp"

#include <algorithm>

#include "core/step_failure.hpp"

namespace soda {

Divergence run_watched(const Model& model, State& state, long long frames, const Stepping& stepping, bool energy,
                       bool reference_step, const FrameCallback& per_frame) {
  // The budget counts from the model's initial state (the FastStepper's scene
  // analysis asks how far masses can get), and `state` may be mid-run.
  FrameStepper stepper(model, stepping, state.frame + frames, reference_step);
  DivergenceMonitor monitor(model, state, {}, energy);
  State next = state;
  for (long long f = 0; f < frames; ++f) {
    if (f % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
    try {
      stepper.step(next);
    } catch (const StepFailure& failure) { // an implicit solve failed: diverged there
      return {true, failure.frame, failure.reason};
    }
    if (!monitor.check(next)) return monitor.result();
    state = next;
    if (per_frame) per_frame(state);
  }
  return {};
}

Divergence run_simulation(const Model& model, State& state, long long frames, const Stepping& stepping, bool energy,
                          bool reference_step, const FrameCallback& per_frame) {
  if (per_frame || energy) return run_watched(model, state, frames, stepping, energy, reference_step, per_frame);
  // Fast path: step in blocks, checking for non-finite values between blocks;
  // on a hit, replay the block frame by frame to stop at the last healthy state.
  FrameStepper stepper(model, stepping, frames, reference_step);
  constexpr long long kBlock = 1024;
  Divergence divergence;
  for (long long done = 0; done < frames && !divergence.diverged;) {
    const long long n = std::min(kBlock, frames - done);
    check_cancellation();
    State block_start = state;
    bool failed = false;
    try {
      stepper.run(state, n);
    } catch (const StepFailure&) {
      failed = true; // replayed frame by frame below, which stops at the failure
    }
    if (failed || first_non_finite(model, state)) {
      state = block_start;
      divergence = run_watched(model, state, n, stepping, false, reference_step);
    }
    done += n;
  }
  return divergence;
}

} // namespace soda
