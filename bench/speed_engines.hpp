// The engines `sodaevo bench speed` times and how it times them: an Engine steps
// one creature or a set of creatures from the initial state for a frame count;
// time_engines calibrates each to a run of about the target time, interleaves the
// engines' runs round by round and reports medians and per-round ratios.
// speed_bench.hpp says which engine is which.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/speed_bench.hpp"
#include "core/model.hpp"

namespace sodaevo::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The clock of time_engines's runs: the wall clock (steady_clock), or with `on` the
/// calling thread's CPU time, which a machine shared with other work does not
/// inflate by the time slices others take (bench speed --cpu-time).
void time_engines_by_cpu(bool on);
/// Seconds on time_engines's clock (a point to subtract from a later one).
double engine_clock();

/// Copy k of `model` with every muscle phase moved by k * 0.0007 cycles: as costly
/// to step as the model, but its sine arguments are its own. Fused scenes compute
/// a sine shared by creatures with the same wave and muscle phase once
/// (core/fused/sine_rows.cpp, fill_rows), so identical copies would overstate what a batch of
/// different creatures gets.
soda::Model shifted_copy(const soda::Model& model, int k);

/// An engine under test: run(frames) steps from the initial state.
struct Engine {
  std::string name;
  std::function<void(long long)> run;
  int creatures = 1; ///< creatures one run steps (each by `frames`)
  /// Called before each run, untimed (none: nothing): fast-batch and fast-replicas
  /// of the ga section copy their initial states here.
  std::function<void()> prepare = nullptr;
};

/// Which engines besides seed, plain, fast-sse2 and fast.
struct EngineChoice {
  bool reference = false;
  bool batch = false;   ///< fast-batch, fast-batch-fused, fast-batch-same
  bool no_wave = false; ///< fast-no-wave (creatures whose muscles need the wave)
};

/// The engines of the creature and size sections on one `model`, which must
/// outlive them.
std::vector<Engine> make_engines(const soda::Model& model, const EngineChoice& choice);

/// The engines of the GA section, on `models` (the creatures of a saved run as the
/// GA steps them): "seed" and "plain" step them one after the other, "fast" with a
/// FastStepper each, "fast-batch" in the batches the GA's evaluation cuts on one
/// thread (evaluation_batch_size, fused_batch_ends), each a soda::BatchStepper.
std::vector<Engine> make_ga_engines(std::shared_ptr<const std::vector<soda::Model>> models);

/// Per creature stepped: the masses and links a row reports; link updates per
/// second are frames per second times `links` (a mean over a set of creatures).
struct Size {
  int masses = 0;
  double links = 0.0;
};

Size size_of(const soda::Model& model);

/// Times every engine on one model (or set of models): calibrated frames,
/// interleaved runs, medians.
std::vector<SpeedRow> time_engines(const std::string& section, const std::string& creature, Size size,
                                   std::vector<Engine> engines, int runs, double target);

} // namespace sodaevo::bench
