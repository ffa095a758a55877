// Stability prediction: will a step of this kind blow up on this creature?
//
// Why: an explicit step of a mass-spring system is stable only while the step is
// short against the fastest vibration, and evolution finds creatures whose
// walk is an integration instability (a numerical exploit). The linearised step
// answers "how far from that edge" from one eigenvalue, without running anything.
//
// The model: near a state, the link accelerations are -K dx (stiffness.hpp), and
// each vibration mode of K with eigenvalue w^2 evolves on its own; gravity is a
// constant and drops out; contact, the syrup limit and the rest test are ignored
// (they only take energy). A step is stable when every mode's amplification
// matrix has spectral radius <= 1; the fastest mode w_max = sqrt(largest
// eigenvalue) decides (docs/stability.md has the derivations):
// - soda (one update per frame, velocity kept by c = 1 - f): stable iff
//   w_max^2 < 2 (1 + c) / c. Continuous Euler is the same update with dt and
//   c = (1 - f)^dt: (w_max dt)^2 < 2 (1 + c) / c.
// - verlet (friction split off exactly): w_max dt < 2, whatever the friction.
// - rk4 with drag lambda: |R(mu dt)| <= 1 for the roots mu of mu^2 + lambda mu + w^2,
//   R the RK4 polynomial; heavy drag alone can make it unstable (lambda dt > 2.785).
// - backward-euler, implicit-midpoint: A-stable, stable at every dt.
// A negative eigenvalue (a compressed link's geometric term) is a physical buckling,
// not a numerical instability, and is not judged here.
//
// Outputs: stable_dt, the largest step (frames) before the scheme turns unstable
// (for soda: the step of a soda-like update with the same c), and
// margin = (stable_dt / dt)^2, which for the soda step is exactly the ratio of the
// two sides, 2 (1 + c) / c over w_max^2: above 1 stable, below 1 unstable.
#pragma once

#include <string>

#include <Eigen/SparseCore>

#include "model.hpp"
#include "stepping.hpp"

namespace soda {

/// Creatures with at most this many degrees of freedom get a dense symmetric
/// eigensolver; larger ones Lanczos (both give the largest eigenvalue of K).
inline constexpr int kDenseEigenLimit = 400;
/// Lanczos stops when the Ritz value's residual is below this share of it.
inline constexpr double kLanczosTolerance = 1e-12;

struct LargestEigenvalue {
  double value = 0.0;   ///< largest eigenvalue of K, 1/frame^2 (0 for no degrees of freedom)
  std::string method;   ///< "dense" or "lanczos"
  int iterations = 0;   ///< Lanczos steps (0 for dense)
};

/// Largest eigenvalue of a symmetric sparse matrix: dense for up to
/// `dense_limit` rows, else Lanczos with full reorthogonalisation, stopped when the
/// residual bound |beta_m s_m| < kLanczosTolerance * |theta| (or the Krylov space
/// is the whole space). Deterministic (fixed start vector).
LargestEigenvalue largest_eigenvalue(const Eigen::SparseMatrix<double>& K, int dense_limit = kDenseEigenLimit);

struct StabilityPrediction {
  double omega_max = 0.0; ///< sqrt of K's largest eigenvalue (0 if <= 0), rad/frame
  double dt = 1.0;        ///< the stepping's step, frames
  double stable_dt = 0.0; ///< largest stable step, frames; +inf when no step is unstable
  double margin = 0.0;    ///< (stable_dt / dt)^2; +inf when no step is unstable
  LargestEigenvalue eigen;
};

/// Prediction for `stepping` at `state` (its wave phase sets the muscle targets).
StabilityPrediction predict_stability(const Model& model, const State& state, const Stepping& stepping);

/// Prediction for a given fastest mode (for tests and the analysis of one scheme).
StabilityPrediction predict_stability(const Model& model, double omega_max, const Stepping& stepping);

/// Whether one step of `dt` frames of `stepping`'s scheme is stable for a mode of
/// angular frequency `omega` (rad/frame) in a world of air friction `friction`.
bool mode_is_stable(const Stepping& stepping, double friction, double omega, double dt);

/// The prediction along a run: the state is stepped `frames` frames with
/// `stepping` from the model's initial state and the prediction taken at frame 0
/// and every `every` frames; the run stops at the first non-finite state.
struct StabilityAlongRun {
  StabilityPrediction first;  ///< at frame 0
  StabilityPrediction lowest; ///< the sample with the smallest margin
  long long lowest_frame = 0;
  int samples = 0;
};
StabilityAlongRun stability_along_run(const Model& model, const Stepping& stepping, long long frames,
                                      long long every);

} // namespace soda
