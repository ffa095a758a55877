// Smooth scenes for measuring integration error: nothing in them touches a wall,
// reaches the 20 px/frame speed limit or rests, so an integrator shows its true
// order. Two have closed-form solutions of the continuous model's ODE
// (core/continuous_step.hpp); the pendulum chain has none and is compared with a
// converged reference (RK4 with many sub-steps).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/model_def.hpp"

namespace sodaevo::bench {

/// An empty 100,000 px box with the given environment and autoreverse off: room
/// for a scene that must not touch a wall.
soda::ModelDef open_world(double gravity, double friction, double springyness);

struct AnalyticScene {
  std::string name;
  soda::ModelDef def;
  /// Exact positions (x0, y0, x1, y1, ... of the free masses) at time t frames,
  /// or empty when the scene has no closed form.
  std::function<std::vector<double>(double t)> exact;
};

/// One mass falling from rest with gravity 0.3 and air friction 0.05:
/// v' = -g - lambda v, lambda = -ln(1 - f), so
/// v(t) = v_inf (1 - e^(-lambda t)), y(t) = y0 + v_inf (t - (1 - e^(-lambda t))/lambda),
/// v_inf = -g/lambda (5.8 px/frame, below the speed limit).
AnalyticScene free_fall_with_friction();

/// Two free masses joined by one spring (k 0.2, rest 100), stretched by 10 px,
/// no gravity, no friction, both drifting up at 1 px/frame (so the spring stays
/// horizontal and neither ever passes the rest test's 1e-5 px/frame): the stretch
/// obeys e'' = -2k e, e(t) = 10 cos(sqrt(2k) t), the midpoint moves uniformly.
AnalyticScene single_spring();

/// Four masses hanging from a fixed node by springs (k 0.05), started sideways,
/// gravity 0.3, friction 0.01, the middle link a muscle driven by the wave: a
/// smooth, chaotic-free 40-frame swing with no contact. No closed form.
AnalyticScene pendulum_chain();

/// A stiff scene: one free mass between two fixed nodes, held by 6 parallel springs
/// (k 0.5) on each side along x, at rest, started 2 px off centre, air friction
/// 0.05, no gravity: x'' = -w^2 x - lambda x' with w^2 = 12k = 6, so
/// x(t) = 2 e^(-lambda t/2) (cos(wd t) + lambda/(2 wd) sin(wd t)), wd^2 = w^2 - lambda^2/4.
/// One update per frame is unstable on it (w^2 = 6 > 2(1+c)/c = 4.1), as are euler
/// and verlet at one step per frame (w dt < 2); rk4 is not (w dt < 2.83); the
/// implicit integrators never are.
AnalyticScene stiff_hub();

std::vector<AnalyticScene> analytic_scenes();

} // namespace sodaevo::bench
