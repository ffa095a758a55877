// The implicit integrators of the continuous mode: backward Euler (order 1) and
// the implicit midpoint rule (order 2), both A-stable, for stiff creatures and
// large steps where the explicit integrators must take many small steps.
//
// Why Newton on the velocity: with x1 = x + dt w the step is one nonlinear system
// in the unknown velocity w (2 unknowns per free mass),
//   G(w) = alpha w - beta v - dt a(x + h w, t_eval) = 0,
//   backward Euler:   alpha = 1 + lambda dt, beta = 1, h = dt,   t_eval = t + dt; v1 = w
//   implicit midpoint: alpha = 2 + lambda dt, beta = 2, h = dt/2, t_eval = t + dt/2; v1 = 2w - v
// (drag -lambda v implicit, lambda = -ln(1 - f)), whose Jacobian
//   J = alpha I + dt h K(x + h w)
// is sparse, symmetric and has the pattern of the stiffness matrix K
// (stiffness.hpp; exact, with the geometric term, so Newton converges
// quadratically). J is factorised with Eigen's SimplicialLDLT; its symbolic
// analysis (the fill-reducing ordering and the elimination tree) depends only on
// the links, so it is done once per stepper and reused by every Newton iteration
// of every step.
//
// Failure: a zero or non-finite pivot, a non-finite iterate, or no convergence in
// kMaxNewtonIterations makes step() return false with the reason; the stepper
// turns that into a StepFailure (step_failure.hpp). Contact, syrup, rest test and
// bars are applied after the smooth step exactly as for Verlet and RK4
// (continuous_step.hpp's finish_mass).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "model.hpp"

namespace soda {

/// Newton stops when the update is below this share of the velocity scale
/// (max |w| + 1 px/frame).
inline constexpr double kNewtonTolerance = 1e-12;
inline constexpr int kMaxNewtonIterations = 30;

class ImplicitSolver {
public:
  /// Acceleration of the free masses at positions (x, y) and wave phase (fixed points get 0).
  using Acceleration = std::function<void(const double* x, const double* y, double phase, double* ax, double* ay)>;

  /// `midpoint`: the implicit midpoint rule, else backward Euler. `drag` = lambda (finite).
  ImplicitSolver(const Model& model, double dt, double drag, bool midpoint, Acceleration acceleration);
  ~ImplicitSolver();
  ImplicitSolver(const ImplicitSolver&) = delete;
  ImplicitSolver& operator=(const ImplicitSolver&) = delete;

  /// One smooth step from (x, y, vx, vy) (point arrays) with the force evaluated at
  /// wave phase `phase_eval`. Writes the end positions and velocities of the free
  /// masses into x1, y1, vx1, vy1 (point arrays; fixed points copied). Returns false
  /// with `why` set when the Newton solve fails; the outputs are then unspecified.
  bool step(const double* x, const double* y, const double* vx, const double* vy, double phase_eval, double* x1,
            double* y1, double* vx1, double* vy1, std::string& why);

private:
  struct Linear; // Eigen's matrix and factorisation, kept out of this header
  const Model& model_;
  double dt_, h_, alpha_, beta_;
  Acceleration acceleration_;
  std::unique_ptr<Linear> linear_;
  std::vector<double> w_, ax_, ay_;
};

} // namespace soda
