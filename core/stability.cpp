#include "stability.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "divergence.hpp"
#include "mix64.hpp"
#include "stiffness.hpp"

namespace soda {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// A spectral radius up to this above 1 counts as stable (the boundary itself,
/// e.g. w dt = 2 without friction, is marginally stable).
constexpr double kRadiusSlack = 1e-12;
/// Steps beyond this many frames are "no limit" (stable_dt = +inf).
constexpr double kNoLimitDt = 1e6;
/// Lanczos runs at most this many steps (its Krylov basis is kept for full
/// reorthogonalisation: memory rows x steps).
constexpr int kMaxLanczosSteps = 400;

/// Spectral radius of the real 2x2 matrix [[a, b], [c, d]].
double spectral_radius(double a, double b, double c, double d) {
  const double trace = a + d;
  const double det = a * d - b * c;
  const double disc = trace * trace / 4.0 - det;
  if (disc < 0.0) return std::sqrt(det); // complex pair: |lambda|^2 = det
  const double root = std::sqrt(disc);
  return std::max(std::fabs(trace / 2.0 + root), std::fabs(trace / 2.0 - root));
}

/// |R(z)|, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24, the RK4 amplification.
double rk4_amplification(std::complex<double> z) {
  return std::abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
}

/// A deterministic start vector with no special structure (splitmix64 values).
Eigen::VectorXd start_vector(int n) {
  Eigen::VectorXd v(n);
  std::uint64_t state = 0x5eed5eedULL;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t z = mix64(state += 0x9e3779b97f4a7c15ULL);
    v[i] = static_cast<double>(z >> 11) / 9007199254740992.0 - 0.5;
  }
  return v.normalized();
}

/// Largest eigenvalue of the symmetric tridiagonal matrix (alpha, beta) of m rows
/// and the last component of its eigenvector.
std::pair<double, double> top_ritz_pair(const std::vector<double>& alpha, const std::vector<double>& beta, int m) {
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i) {
    T(i, i) = alpha[static_cast<std::size_t>(i)];
    if (i + 1 < m) T(i, i + 1) = T(i + 1, i) = beta[static_cast<std::size_t>(i)];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(T);
  return {es.eigenvalues()[m - 1], es.eigenvectors()(m - 1, m - 1)};
}

LargestEigenvalue lanczos_largest(const Eigen::SparseMatrix<double>& K) {
  const int n = static_cast<int>(K.rows());
  const int max_steps = std::min(n, kMaxLanczosSteps);
  Eigen::MatrixXd Q(n, max_steps);
  std::vector<double> alpha, beta;
  Q.col(0) = start_vector(n);
  LargestEigenvalue out;
  out.method = "lanczos";
  for (int j = 0; j < max_steps; ++j) {
    Eigen::VectorXd w = K * Q.col(j);
    alpha.push_back(Q.col(j).dot(w));
    // Full reorthogonalisation, twice ("twice is enough"): keeps the Ritz values
    // free of ghost copies at the cost of O(n j) per step.
    for (int pass = 0; pass < 2; ++pass) w -= Q.leftCols(j + 1) * (Q.leftCols(j + 1).transpose() * w);
    const double b = w.norm();
    beta.push_back(b);
    const int m = j + 1;
    const bool exhausted = m == max_steps || b <= 1e-14 * std::max(1.0, std::fabs(alpha.back()));
    if (exhausted || m % 8 == 0) {
      const auto [theta, last] = top_ritz_pair(alpha, beta, m);
      out.value = theta;
      out.iterations = m;
      if (exhausted || b * std::fabs(last) <= kLanczosTolerance * std::max(std::fabs(theta), 1e-300)) return out;
    }
    Q.col(j + 1) = w / b;
  }
  return out;
}

/// Modes whose stability decides a scheme: the fastest alone, except for RK4, whose
/// drag term can make slow modes unstable too.
std::vector<double> decisive_modes(const Stepping& s, double omega_max) {
  if (s.mode == PhysicsMode::Continuous && s.integrator == Integrator::Rk4) {
    std::vector<double> modes;
    for (int i = 0; i <= 32; ++i) modes.push_back(omega_max * i / 32.0);
    return modes;
  }
  return {omega_max};
}

bool all_stable(const Stepping& s, double friction, const std::vector<double>& modes, double dt) {
  return std::all_of(modes.begin(), modes.end(), [&](double w) { return mode_is_stable(s, friction, w, dt); });
}

/// The largest step before the scheme turns unstable: a geometric scan from a
/// step far below 1/w_max, then bisection to the last bit.
double stable_dt_of(const Stepping& s, double friction, double omega_max) {
  const std::vector<double> modes = decisive_modes(s, omega_max);
  double lo = omega_max > 0.0 ? 1e-3 / omega_max : 1e-3;
  if (!all_stable(s, friction, modes, lo)) return 0.0;
  double hi = lo;
  while (all_stable(s, friction, modes, hi)) {
    lo = hi;
    hi *= 1.02;
    if (hi > kNoLimitDt) return kInfinity;
  }
  for (int i = 0; i < 200 && std::nextafter(lo, hi) < hi; ++i) {
    const double mid = lo + (hi - lo) / 2.0;
    (all_stable(s, friction, modes, mid) ? lo : hi) = mid;
  }
  return lo;
}

} // namespace

LargestEigenvalue largest_eigenvalue(const Eigen::SparseMatrix<double>& K, int dense_limit) {
  const int n = static_cast<int>(K.rows());
  LargestEigenvalue out;
  if (n == 0) {
    out.method = "dense";
    return out;
  }
  if (n > dense_limit) return lanczos_largest(K);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Eigen::MatrixXd(K), Eigen::EigenvaluesOnly);
  out.value = es.eigenvalues()[n - 1];
  out.method = "dense";
  return out;
}

bool mode_is_stable(const Stepping& s, double friction, double omega, double dt) {
  const double w2dt2 = omega * omega * dt * dt;
  // The soda mode's step is the semi-implicit Euler step. No default: a new
  // integrator must say here whether it is stable (-Wswitch, an error in CI).
  switch (s.mode == PhysicsMode::Soda ? Integrator::Euler : s.integrator) {
    case Integrator::Euler: {
      // (x, dt v) -> x' = x + c (dt v - s x), dt v' = c (dt v - s x): [[1 - c s, c], [-c s, c]]
      const double c = s.mode == PhysicsMode::Soda ? 1.0 - friction : std::pow(1.0 - friction, dt);
      return spectral_radius(1.0 - c * w2dt2, c, -c * w2dt2, c) <= 1.0 + kRadiusSlack;
    }
    case Integrator::Verlet: {
      // kick-drift-kick between the friction halves h = (1 - f)^(dt/2); det = h^4, trace (1 + h^2)(1 - s/2)
      const double h = std::pow(1.0 - friction, dt / 2.0);
      return spectral_radius(1.0 - w2dt2 / 2.0, h, -h * w2dt2 * (1.0 - w2dt2 / 4.0), h * h * (1.0 - w2dt2 / 2.0)) <=
             1.0 + kRadiusSlack;
    }
    case Integrator::Rk4: {
      if (friction >= 1.0) return true; // infinite drag: the stepper stops every mass
      const double lambda = -std::log1p(-friction);
      const std::complex<double> root = std::sqrt(std::complex<double>(lambda * lambda / 4.0 - omega * omega, 0.0));
      const std::complex<double> mu1 = -lambda / 2.0 + root, mu2 = -lambda / 2.0 - root;
      return rk4_amplification(mu1 * dt) <= 1.0 + kRadiusSlack && rk4_amplification(mu2 * dt) <= 1.0 + kRadiusSlack;
    }
    case Integrator::BackwardEuler:
    case Integrator::ImplicitMidpoint: return true; // implicit schemes are A-stable
  }
  throw std::logic_error("mode_is_stable: integrator " + std::to_string(static_cast<int>(s.integrator)));
}

StabilityPrediction predict_stability(const Model& model, double omega_max, const Stepping& stepping) {
  StabilityPrediction p;
  p.omega_max = omega_max;
  p.dt = stepping.mode == PhysicsMode::Soda ? 1.0 : 1.0 / static_cast<double>(stepping.substeps);
  p.stable_dt = stable_dt_of(stepping, model.friction, omega_max);
  p.margin = std::isinf(p.stable_dt) ? kInfinity : (p.stable_dt / p.dt) * (p.stable_dt / p.dt);
  return p;
}

StabilityPrediction predict_stability(const Model& model, const State& state, const Stepping& stepping) {
  validate_stepping(stepping);
  const LargestEigenvalue top = largest_eigenvalue(stiffness_matrix(model, state));
  StabilityPrediction p = predict_stability(model, std::sqrt(std::max(top.value, 0.0)), stepping);
  p.eigen = top;
  return p;
}

StabilityAlongRun stability_along_run(const Model& model, const Stepping& stepping, long long frames,
                                      long long every) {
  if (every < 1) throw std::invalid_argument("stability_along_run: every must be >= 1");
  State state = make_state(model);
  StabilityAlongRun out;
  out.first = predict_stability(model, state, stepping);
  out.lowest = out.first;
  out.samples = 1;
  FrameStepper stepper(model, stepping, frames);
  for (long long done = 0; done < frames;) {
    const long long n = std::min(every, frames - done);
    stepper.run(state, n);
    done += n;
    if (first_non_finite(model, state)) break;
    const StabilityPrediction p = predict_stability(model, state, stepping);
    ++out.samples;
    if (p.margin < out.lowest.margin) {
      out.lowest = p;
      out.lowest_frame = done;
    }
  }
  return out;
}

} // namespace soda
