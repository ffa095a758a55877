// A step that could not be taken: an implicit integrator's Newton solve that met
// a singular matrix or did not converge. Thrown by the stepper with the state left
// at the last completed frame, so nothing half-stepped or non-finite escapes; the
// callers that watch for divergence (simulate, fitness, the benchmarks) mark the
// run diverged with this reason and frame, as for a non-finite state.
#pragma once

#include <stdexcept>
#include <string>

namespace soda {

struct StepFailure : std::runtime_error {
  StepFailure(long long frame_, const std::string& reason_)
      : std::runtime_error(reason_ + " (frame " + std::to_string(frame_) + ")"), frame(frame_), reason(reason_) {}
  long long frame = 0; ///< the frame that could not be completed
  std::string reason;
};

} // namespace soda
