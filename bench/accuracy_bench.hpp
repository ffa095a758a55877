// The work-precision benchmark (`sodaevo bench accuracy`): for the soda mode and
// every integrator of the continuous mode at dt = 1 to 1/64 frame, run time
// against error.
//
// Error is measured against the truth where it exists and against a converged
// reference otherwise:
// - analytic scenes (analytic_scenes.hpp): largest position error at fixed times
//   (10, 20 and 40 frames) against the closed form, or against RK4 at 1024
//   sub-steps for the pendulum chain;
// - the bundled classics (models/*.xml), prepared as the GA prepares a creature
//   (wide container, autoreverse off) in their own world, unscaled: error of the
//   distance walked by the centroid after the settle frames and N scored frames,
//   against RK4 at 256 sub-steps (its distance at 128 sub-steps is reported too, as
//   the reference's own uncertainty), and the position error at frame 100;
// - random walkers (evolve/variation.hpp random_creature in the default world,
//   prepared with Sodarace scaling as the GA does): how well each setting keeps the
//   ranking by distance walked (after 100 and after N scored frames), Kendall's
//   tau-b against the reference, and the median relative distance error. Most
//   random creatures tumble chaotically, so the reference at half its sub-steps is
//   ranked too: its tau is the best any setting can be expected to reach.
// Run time is wall time per simulated frame on one thread (analytic scenes and
// classics: the fastest of 3 identical runs, as the machine may be shared); soda runs
// the plain reference step (a scalar loop like the continuous stepper), so the
// timings compare methods; the SIMD FastStepper makes soda several times faster
// still (results/bench/speed.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/stepping.hpp"

namespace sodaevo::bench {

struct AccuracyOptions {
  bool quick = false; ///< fewer walkers and frames: a smoke test in seconds
  std::vector<std::pair<std::string, std::string>> classics; ///< name, model path
  int walkers = 200;
  long long walker_frames = 1000;
  long long classic_frames = 2000;
  long long settle_frames = 100;
  int max_substeps = 64;        ///< substeps 1, 2, 4, ... up to this
  int reference_substeps = 256; ///< RK4 reference for classics and walkers
  std::uint64_t seed = 1;
  int timing_runs = 3; ///< analytic scenes and classics: run time = fastest of this many runs
  std::function<void(const std::string&)> progress;
};

struct AccuracyRow {
  std::string section; ///< "analytic", "classic" or "walkers"
  std::string scene;
  soda::Stepping stepping;
  double seconds_per_frame = 0.0;
  double position_error = 0.0;   ///< px (analytic: max over fixed times; classic: at frame 100)
  double distance = 0.0;         ///< classic: px walked; walkers: not used
  double reference_distance = 0.0;
  double distance_error = 0.0;   ///< classic: |distance - reference| / max(|reference|, 1 px); walkers: median of that
  double kendall_tau = 0.0;      ///< walkers only: ranking by distance after all scored frames
  double kendall_tau_short = 0.0; ///< walkers only: ranking by distance after 100 scored frames
  double kendall_tau_movers = 0.0; ///< walkers only: all frames, only walkers whose reference moves >= 0.1 px/frame
  int diverged = 0;              ///< runs flagged diverged
};

struct AccuracyReport {
  std::vector<AccuracyRow> rows;
  /// Classic walkers whose reference distance exceeds 50 px (the others stand
  /// still or spin, and a relative distance error means nothing for them).
  std::vector<std::string> walkers_among_classics;
  std::vector<std::pair<std::string, double>> reference_uncertainty; ///< classic: |d(256) - d(128)| / |d(256)|
  /// Kendall tau of the reference at half its sub-steps against the reference:
  /// the best agreement any setting can show (chaos makes it well below 1).
  double walkers_noise_floor_tau = 0.0;
  double walkers_noise_floor_tau_short = 0.0;
  double walkers_noise_floor_tau_movers = 0.0;
  int walkers_movers = 0; ///< walkers whose reference moves at least 0.1 px/frame
};

AccuracyReport run_accuracy_bench(const AccuracyOptions& options);

/// The implicit integrators are swept only up to this many sub-steps: a Newton
/// solve costs tens of explicit steps, and their case is the large step.
inline constexpr int kImplicitMaxSubsteps = 8;
/// kImplicitMaxSubsteps for the implicit integrators, else no limit.
int swept_max_substeps(soda::Integrator integrator);

/// The settings swept: soda, then every integrator at 1, 2, 4, ... max_substeps
/// (the implicit ones up to kImplicitMaxSubsteps).
std::vector<soda::Stepping> swept_settings(int max_substeps);

/// Kendall's tau-b of two equally long samples (ties handled); 1 = same order.
double kendall_tau(const std::vector<double>& a, const std::vector<double>& b);

} // namespace sodaevo::bench
