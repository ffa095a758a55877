// One model run for N frames as `sodaevo simulate` runs it, watched for
// divergence: the command line and the Python module (python/) both call this,
// so a run from Python is the command's run, bit for bit.
//
// Two paths with the same bits: with a per-frame callback (a trace) or the
// energy check, frame by frame; otherwise in blocks, checking for non-finite
// values between blocks and replaying a block frame by frame on a hit, so that a
// run stops at its last healthy state either way.
#pragma once

#include <functional>

#include "core/divergence.hpp"
#include "core/model.hpp"
#include "core/stepping.hpp"

namespace soda {

/// Called with every healthy state after a step.
using FrameCallback = std::function<void(const State&)>;

/// Runs `frames` frames watching for divergence; stops at the first diverged
/// frame, keeping the last healthy state in `state` (nothing non-finite is
/// reported or written). `per_frame` (may be empty) sees every healthy state.
/// `energy`: runaway energy counts as divergence too (core/divergence.hpp).
Divergence run_watched(const Model& model, State& state, long long frames, const Stepping& stepping, bool energy,
                       bool reference_step, const FrameCallback& per_frame = {});

/// run_watched's result, fast: frame by frame only when `per_frame` or `energy`
/// asks for every frame, else in blocks (same bits, same stop).
Divergence run_simulation(const Model& model, State& state, long long frames, const Stepping& stepping, bool energy,
                          bool reference_step, const FrameCallback& per_frame = {});

} // namespace soda
