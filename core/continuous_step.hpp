// The `continuous` mode: the SodaConstructor model read as an ODE and stepped with
// dt = 1/substeps frame (docs/continuous-mode.md).
//
// Why: the original takes one semi-implicit Euler step per frame. That is the
// model, for walkers bred in it, but it is also a coarse integration of a
// mass-spring system, and evolution exploits integration error. Stepping the same
// forces with smaller dt and better integrators tells how much of a creature's walk
// is physics and how much is the step (bench/accuracy_bench.hpp, evolve/problems/honesty.hpp).
//
// The model as an ODE (per free mass, mass 1, time in frames, velocity in px/frame):
//   x' = v,   v' = sum over links of k*(L - D(t))*u  +  gravity  -  lambda*v,
// with lambda = -ln(1 - f), so that air friction over one frame is exactly the
// original's factor (1 - f), and the wave phase phi(t) = phi0 + speed*mode*t.
// The per-frame impulses of the original become forces per frame^2.
//
// What is not smooth, and how each piece is treated at a sub-frame step (the same
// for every integrator, applied after the smooth update of the step):
// - Syrup (speed limit 20 px/frame): a speed, not a rate, so the same limit is
//   applied after every step. Euler applies it where the original does (after
//   gravity and friction, before the move); Verlet and RK4 after the step.
// - Rest test (|vx|, |vy| < 1e-5 px/frame): also a speed; a mass below it is not
//   moved that step. Its effect on position is below 1e-5*dt px per step.
// - Container contact: a position clamp plus a velocity response. Reflection Rs is
//   an impact law (the share of normal velocity kept by one impact), so it applies
//   once per step in contact, unchanged. Surface friction Fs is the share of
//   tangential velocity kept per frame of contact, so it becomes Fs^dt per step
//   in contact: a mass resting on the floor for one frame loses the same share as
//   in the original. Corner rule and autoreverse as in the original, per step.
// - Fixed bars: the original rules (fixed_bars.hpp) for the move of one step, with
//   Fs^dt as the surface friction of the slide.
// - Wave: advances speed*dt per step (wrapped); muscles see the phase of the time
//   at which the integrator evaluates the force (RK4 stages at t + dt/2, t + dt).
// Contact, syrup and the rest test are first-order events: an integrator reaches
// its order only while none of them acts (the analytic scenes of the tests).
//
// Integrators (dt = 1/substeps):
// - euler: semi-implicit (symplectic) Euler in the original's exact order of
//   operations: links, then per mass gravity, friction (1-f)^dt, syrup, rest
//   test, move, contact; then the wave. With substeps = 1 every product by dt is a
//   product by 1, and the step equals soda::step bit for bit (tested).
// - verlet: velocity Verlet (kick-drift-kick), air friction split off and applied
//   exactly as (1-f)^(dt/2) before and after (Strang splitting): order 2.
// - rk4: classic Runge-Kutta 4 on (x, v) with friction as the drag -lambda*v:
//   order 4. With f = 1 (infinite drag) nothing moves, the ODE's limit.
// - backward-euler, implicit-midpoint: implicit, orders 1 and 2, drag -lambda*v
//   implicit, one Newton solve per step (implicit_step.hpp); then syrup, rest test,
//   container and bars as for Verlet and RK4. A failed solve throws StepFailure
//   (step_failure.hpp) with the state left at the start of the frame.
#pragma once

#include <memory>
#include <vector>

#include "model.hpp"
#include "stepping.hpp"

namespace soda {

struct ContinuousSettings {
  Integrator integrator = Integrator::Euler;
  int substeps = 1; ///< [1, kMaxSubsteps]
};

class ImplicitSolver;

class ContinuousStepper {
public:
  /// Throws InputError for a bad sub-step count. `model` must outlive the stepper.
  ContinuousStepper(const Model& model, ContinuousSettings settings);
  ~ContinuousStepper();
  ContinuousStepper(const ContinuousStepper&) = delete; // the implicit solver calls back into this one
  ContinuousStepper& operator=(const ContinuousStepper&) = delete;

  /// One frame: `substeps` steps of dt; state.frame advances by 1. The implicit
  /// integrators throw StepFailure (state unchanged) when a Newton solve fails.
  void step(State& state);
  void run(State& state, long long frames);

  [[nodiscard]] double dt() const { return dt_; }

private:
  void step_unchecked(State& s); ///< step() after its check of the state
  void euler_step(State& s);
  void verlet_step(State& s);
  void rk4_step(State& s);
  /// false with `why` when the Newton solve fails (s then unchanged)
  bool implicit_step(State& s, std::string& why);
  /// f = 1: infinite drag stops every mass (the ODE's limit); the wave goes on.
  void stop_all(State& s) const;
  /// Link forces plus gravity on every free mass at positions (x, y) and wave
  /// phase `phase` (fixed nodes get 0), with the state's sine jitter. Links in file order.
  void smooth_acceleration(const double* x, const double* y, double phase, const SineJitter& jitter, double* ax,
                           double* ay) const;
  /// Syrup, rest test, container and bars for mass i after a smooth update that
  /// moved it from (x0, y0) to (x, y) with end velocity (vx, vy).
  void finish_mass(State& s, int i, double x0, double y0, double x, double y, double vx, double vy) const;
  void advance_wave(State& s) const;

  const Model& model_;
  ContinuousSettings settings_;
  double dt_ = 1.0;
  double keep_ = 1.0;        ///< (1 - f)^dt
  double keep_half_ = 1.0;   ///< (1 - f)^(dt/2)
  double drag_ = 0.0;        ///< lambda = -ln(1 - f), +inf for f = 1
  double surface_keep_ = 1.0; ///< Fs^dt
  double gravity_step_ = 0.0; ///< g*dt
  double wave_step_ = 0.0;    ///< wave speed*dt
  std::unique_ptr<ImplicitSolver> implicit_; ///< backward-euler, implicit-midpoint (finite drag)
  const SineJitter* solving_jitter_ = nullptr; ///< the jitter of the state the solver is stepping
  // scratch, [point_count]
  std::vector<double> ax_, ay_, x1_, y1_, vx1_, vy1_, kx_, ky_, kvx_, kvy_;
};

} // namespace soda
