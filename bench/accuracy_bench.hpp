// The work-precision benchmark (`sodaevo bench accuracy`): for the soda mode and
// every integrator of the continuous mode at dt = 1 to 1/64 frame, run time
// against error.
//
// Error is measured against the truth where it exists and against a converged
// reference otherwise:
// - analytic scenes (analytic_scenes.hpp): largest position error at fixed times
//   (10, 20 and 40 frames) against the closed form, or against RK4 at 1024
//   sub-steps for the pendulum chain;
// - the bundled classics (models/*.xml) and the GA's own champions
//   (models/champions/), prepared as the GA prepares a creature (wide container,
//   autoreverse off) in their own world, unscaled: the expected distance walked by
//   the centroid after the settle frames and N scored frames (the mean over R
//   sine-jitter replicas, bench/replica_runs.hpp), against the reference's expected
//   distance (RK4 at 128 sub-steps), with a 95 % interval; the reference at half its
//   sub-steps against itself is its own uncertainty. The single exact rollout's
//   error (replica 0 against the reference's replica 0) is kept for comparison, and
//   the position error at frame 100 (replica 0, before chaos sets in);
// - random walkers (evolve/algorithms/variation.hpp random_creature in the default world,
//   prepared with Sodarace scaling as the GA does): how well each setting keeps the
//   ranking by expected distance, Kendall's tau-b against the reference, among the
//   walkers that move and over all. The reference at half its sub-steps ranks them
//   too: its tau is the noise floor, the best any setting can be expected to reach;
//   the tau two independent R-replica estimates of the same expectations would show
//   (from the reference's standard errors) says how much of it R replicas explain.
// Run time is wall time per simulated frame on one thread (analytic scenes: the
// fastest of 3 identical runs; creatures: the fastest replica, as the machine may be
// shared); soda runs the plain reference step (a scalar loop like the continuous
// stepper, and the stepper that applies the jitter), so the timings compare methods;
// the SIMD FastStepper makes soda several times faster still (results/bench/speed.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/stepping.hpp"

namespace sodaevo::bench {

struct AccuracyOptions {
  bool quick = false; ///< fewer walkers, replicas and frames: a smoke test in seconds
  std::vector<std::pair<std::string, std::string>> classics;  ///< name, model path
  std::vector<std::pair<std::string, std::string>> champions; ///< name, model path: the GA's own
  int walkers = 100;
  long long walker_frames = 1000;
  long long classic_frames = 1000;
  long long settle_frames = 100;
  int max_substeps = 32;        ///< substeps 1, 2, 4, ... up to this (classics, champions)
  int walker_max_substeps = 16; ///< the same for the random walkers (R replicas of each: the costly part)
  int reference_substeps = 128; ///< RK4 reference for classics, champions and walkers
  int replicas = 6;             ///< R: replica 0 exact, replica r jittered with seed r
  double jitter = 0.002;        ///< share of sines a jittered replica moves by 1 ulp
  std::uint64_t seed = 1;
  int timing_runs = 3; ///< analytic scenes: run time = fastest of this many runs
  std::function<void(const std::string&)> progress;
};

struct AccuracyRow {
  std::string section; ///< "analytic", "classic", "champion" or "walkers"
  std::string scene;
  soda::Stepping stepping;
  double seconds_per_frame = 0.0;
  double position_error = 0.0; ///< px (analytic: max over fixed times; creatures: replica 0 at frame 100)
  // Creatures (classic, champion): expected distances over the replicas.
  double distance = 0.0;           ///< mean over replicas, px
  double distance_se = 0.0;        ///< its standard error
  double reference_distance = 0.0; ///< the reference's mean
  double reference_se = 0.0;
  /// creatures: |mean - reference mean| / max(|reference mean|, 1 px); walkers: the
  /// median of that over the movers
  double distance_error = 0.0;
  double error_low = 0.0, error_high = 0.0; ///< creatures: 95 % interval of (mean - reference mean) / that scale
  double exact_distance = 0.0; ///< replica 0's distance (the single exact rollout)
  double exact_error = 0.0;    ///< replica 0 against the reference's replica 0, relative (walkers: median, movers)
  // Random walkers.
  double kendall_tau = 0.0;              ///< ranking by expected distance, all walkers
  double kendall_tau_movers = 0.0;       ///< ranking by expected distance, walkers that move
  double kendall_tau_exact_movers = 0.0; ///< ranking by replica 0 alone (one rollout each), movers
  int diverged = 0; ///< creatures: replicas that diverged; walkers: walkers with a diverged replica
};

/// A creature's reference: its expected distance and how far the reference moves
/// at half its sub-steps.
struct CreatureReference {
  std::string section, name;
  double distance = 0.0, standard_error = 0.0, sd = 0.0;
  double half_width = 0.0; ///< of the mean's 95 % confidence interval, t(0.975, n - 1) * standard error
  double half_step_change = 0.0; ///< (half-step mean - mean) / max(|mean|, 1 px)
  double half_step_low = 0.0, half_step_high = 0.0; ///< its 95 % interval
};

struct AccuracyReport {
  std::vector<AccuracyRow> rows;
  int replicas = 0;
  soda::Stepping reference;
  long long creature_frames = 0, settle_frames = 0; ///< classics and champions: scored after settle
  std::vector<CreatureReference> references; ///< classics, then champions
  /// Creatures whose reference distance exceeds 50 px (the others stand still or
  /// spin, and a relative distance error means nothing for them).
  std::vector<std::string> walkers_among_classics;
  std::vector<std::string> walkers_among_champions;
  /// Kendall tau of the reference at half its sub-steps against the reference,
  /// ranking by expected distance: the best agreement any setting can show.
  double walkers_noise_floor_tau = 0.0;
  double walkers_noise_floor_tau_movers = 0.0;
  double walkers_noise_floor_tau_exact_movers = 0.0; ///< the same by one rollout each (replica 0)
  /// The tau two independent estimates from R (and 4R, 16R) replicas of the movers'
  /// expected distances would show, from the reference's means and standard errors:
  /// the mean over pairs of (2 Phi(|d| / s) - 1)^2, s the pair's combined standard error.
  double walkers_predicted_tau_movers = 0.0;
  double walkers_predicted_tau_movers_4r = 0.0;
  double walkers_predicted_tau_movers_16r = 0.0;
  double walkers_median_relative_se = 0.0; ///< movers: median of the reference's standard error / |mean|
  int walkers = 0;
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

/// The expected Kendall tau of two independent noisy estimates of `means`, each
/// value with standard error `errors[i]` (normal): the mean over pairs of
/// (2 Phi(|m_i - m_j| / sqrt(e_i^2 + e_j^2)) - 1)^2; 1 with no noise.
double predicted_tau(const std::vector<double>& means, const std::vector<double>& errors);

} // namespace sodaevo::bench
