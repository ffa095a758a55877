#include "continuous_step.hpp"
#include "core/cancellation.hpp"

#include <cmath>
#include <limits>

#include "implicit_step.hpp"
#include "physics_rules.hpp"
#include "step.hpp"
#include "step_failure.hpp"

namespace soda {

ContinuousStepper::ContinuousStepper(const Model& model, ContinuousSettings settings)
    : model_(model), settings_(settings) {
  validate_stepping({PhysicsMode::Continuous, settings.integrator, settings.substeps});
  const bool whole_frame = settings.substeps == 1;
  dt_ = 1.0 / static_cast<double>(settings.substeps);
  // With one step per frame the per-step factors are the original's own numbers
  // (pow(x, 1) is x anyway; this says it).
  keep_ = whole_frame ? 1.0 - model.friction : std::pow(1.0 - model.friction, dt_);
  keep_half_ = std::pow(1.0 - model.friction, dt_ / 2.0);
  drag_ = model.friction < 1.0 ? -std::log1p(-model.friction) : std::numeric_limits<double>::infinity();
  surface_keep_ = whole_frame ? model.surface_friction : std::pow(model.surface_friction, dt_);
  gravity_step_ = model.gravity * dt_;
  wave_step_ = model.wave_speed * dt_;
  const auto n = static_cast<std::size_t>(model.point_count);
  for (auto* v : {&ax_, &ay_, &x1_, &y1_, &vx1_, &vy1_, &kx_, &ky_, &kvx_, &kvy_}) v->assign(n, 0.0);
  const bool implicit =
      settings.integrator == Integrator::BackwardEuler || settings.integrator == Integrator::ImplicitMidpoint;
  if (implicit && std::isfinite(drag_)) {
    implicit_ = std::make_unique<ImplicitSolver>(
        model, dt_, drag_, settings.integrator == Integrator::ImplicitMidpoint,
        [this](const double* x, const double* y, double phase, double* ax, double* ay) {
          smooth_acceleration(x, y, phase, *solving_jitter_, ax, ay);
        });
  }
}

ContinuousStepper::~ContinuousStepper() = default;

void ContinuousStepper::step(State& s) {
  require_state_size(s, model_.point_count, "ContinuousStepper::step");
  step_unchecked(s);
}

void ContinuousStepper::step_unchecked(State& s) {
  const bool implicit =
      settings_.integrator == Integrator::BackwardEuler || settings_.integrator == Integrator::ImplicitMidpoint;
  if (implicit) {
    // A failed solve leaves the state at the start of the frame: copy it (cheap
    // next to the factorisations).
    const State start = s;
    std::string why;
    for (int k = 0; k < settings_.substeps; ++k) {
      if (!implicit_step(s, why)) {
        s = start;
        throw StepFailure(s.frame + 1, integrator_name(settings_.integrator) + ": " + why + " in step " +
                                           std::to_string(k + 1) + " of the frame");
      }
    }
    ++s.frame;
    return;
  }
  for (int k = 0; k < settings_.substeps; ++k) {
    switch (settings_.integrator) {
      case Integrator::Euler: euler_step(s); break;
      case Integrator::Verlet: verlet_step(s); break;
      case Integrator::Rk4: rk4_step(s); break;
      case Integrator::BackwardEuler:
      case Integrator::ImplicitMidpoint: break; // above
    }
  }
  ++s.frame;
}

void ContinuousStepper::stop_all(State& s) const {
  for (int i = 0; i < model_.mass_count; ++i) {
    s.vx[i] = 0.0;
    s.vy[i] = 0.0;
  }
  advance_wave(s);
}

bool ContinuousStepper::implicit_step(State& s, std::string& why) {
  if (!implicit_) { // f = 1
    stop_all(s);
    return true;
  }
  solving_jitter_ = &s.jitter;
  const bool midpoint = settings_.integrator == Integrator::ImplicitMidpoint;
  const double phase_eval =
      rules::advance_wave_phase(s.wave_phase, midpoint ? wave_step_ / 2.0 : wave_step_, s.wave_mode);
  if (!implicit_->step(s.x.data(), s.y.data(), s.vx.data(), s.vy.data(), phase_eval, x1_.data(), y1_.data(),
                       vx1_.data(), vy1_.data(), why)) {
    return false;
  }
  for (int i = 0; i < model_.mass_count; ++i) finish_mass(s, i, s.x[i], s.y[i], x1_[i], y1_[i], vx1_[i], vy1_[i]);
  advance_wave(s);
  return true;
}

void ContinuousStepper::run(State& s, long long frames) {
  require_state_size(s, model_.point_count, "ContinuousStepper::run");
  for (long long f = 0; f < frames; ++f) {
    if (f % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
    step_unchecked(s);
  }
}

void ContinuousStepper::advance_wave(State& s) const {
  s.wave_phase = rules::advance_wave_phase(s.wave_phase, wave_step_, s.wave_mode);
}

// The reference step's own code: with dt_ = 1 every product by dt_ is exact, so it
// equals soda::step bit for bit.
void ContinuousStepper::euler_step(State& s) {
  soda::euler_step(model_, s, {dt_, gravity_step_, keep_, surface_keep_, wave_step_});
}

void ContinuousStepper::smooth_acceleration(const double* x, const double* y, double phase, const SineJitter& jitter,
                                            double* ax, double* ay) const {
  const Model& m = model_;
  for (int p = 0; p < m.point_count; ++p) {
    ax[p] = 0.0;
    ay[p] = 0.0;
  }
  const int links = m.link_count();
  for (int i = 0; i < links; ++i) {
    const int a = m.link_a[i];
    const int b = m.link_b[i];
    const double dx = x[b] - x[a];
    const double dy = y[b] - y[a];
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0.0) continue;
    const double target = rules::link_target_length(m, i, phase, jitter);
    const double c = rules::link_impulse_factor(m.springyness, length, target);
    ax[a] += c * dx;
    ay[a] += c * dy;
    ax[b] -= c * dx;
    ay[b] -= c * dy;
  }
  for (int i = 0; i < m.mass_count; ++i) ay[i] = rules::apply_gravity(ay[i], m.gravity, m.gravity_direction);
  for (int p = m.mass_count; p < m.point_count; ++p) {
    ax[p] = 0.0;
    ay[p] = 0.0;
  }
}

void ContinuousStepper::finish_mass(State& s, int i, double x0, double y0, double x, double y, double vx,
                                    double vy) const {
  const Model& m = model_;
  const double syrup = rules::syrup_factor(vx, vy);
  vx = syrup * vx;
  vy = syrup * vy;
  if (rules::is_at_rest(vx, vy)) {
    s.x[i] = x0;
    s.y[i] = y0;
    s.vx[i] = vx;
    s.vy[i] = vy;
    return;
  }
  const MassMove move = rules::mass_move(x0, y0, x, y, vx, vy);
  const bool crossed_floor_or_ceiling = y < 0.0 || y > m.height;
  const bool crossed_side_wall = x < 0.0 || x > m.width;
  const SideWall hit =
      rules::collide_with_container(x, y, vx, vy, m.width, m.height, surface_keep_, m.surface_reflection);
  rules::friction_while_touching(y0 <= 0.0 || y0 >= m.height, x0 <= 0.0 || x0 >= m.width, crossed_floor_or_ceiling,
                                 crossed_side_wall, vx, vy, surface_keep_);
  rules::complete_move(m, s, i, hit, surface_keep_, move, x, y, vx, vy);
}

// Kick-drift-kick with Strang-split air friction:
// v *= keep^(1/2); v += a(x, t)*dt/2; x += v*dt; v += a(x', t + dt)*dt/2; v *= keep^(1/2).
void ContinuousStepper::verlet_step(State& s) {
  const Model& m = model_;
  const int n = m.mass_count;
  const double half = dt_ / 2.0;
  smooth_acceleration(s.x.data(), s.y.data(), s.wave_phase, s.jitter, ax_.data(), ay_.data());
  x1_ = s.x; // fixed nodes keep their place in the drifted positions
  y1_ = s.y;
  for (int i = 0; i < n; ++i) {
    vx1_[i] = s.vx[i] * keep_half_ + ax_[i] * half;
    vy1_[i] = s.vy[i] * keep_half_ + ay_[i] * half;
    // The rest test as a speed: a mass this slow does not drift this step.
    if (!rules::is_at_rest(vx1_[i], vy1_[i])) {
      x1_[i] = s.x[i] + vx1_[i] * dt_;
      y1_[i] = s.y[i] + vy1_[i] * dt_;
    }
  }
  const double phase_end = rules::advance_wave_phase(s.wave_phase, wave_step_, s.wave_mode);
  smooth_acceleration(x1_.data(), y1_.data(), phase_end, s.jitter, ax_.data(), ay_.data());
  for (int i = 0; i < n; ++i) {
    const double vx = (vx1_[i] + ax_[i] * half) * keep_half_;
    const double vy = (vy1_[i] + ay_[i] * half) * keep_half_;
    finish_mass(s, i, s.x[i], s.y[i], x1_[i], y1_[i], vx, vy);
  }
  advance_wave(s);
}

void ContinuousStepper::rk4_step(State& s) {
  const Model& m = model_;
  const int n = m.mass_count;
  if (!std::isfinite(drag_)) { // f = 1: infinite drag, nothing moves (the ODE's limit)
    stop_all(s);
    return;
  }
  const double half = dt_ / 2.0;
  const double phase_half = rules::advance_wave_phase(s.wave_phase, wave_step_ / 2.0, s.wave_mode);
  const double phase_end = rules::advance_wave_phase(s.wave_phase, wave_step_, s.wave_mode);
  x1_ = s.x;
  y1_ = s.y;
  // Stage 1 at (x, v, t).
  smooth_acceleration(s.x.data(), s.y.data(), s.wave_phase, s.jitter, ax_.data(), ay_.data());
  for (int i = 0; i < n; ++i) {
    const double avx = ax_[i] - drag_ * s.vx[i];
    const double avy = ay_[i] - drag_ * s.vy[i];
    kx_[i] = s.vx[i];
    ky_[i] = s.vy[i];
    kvx_[i] = avx;
    kvy_[i] = avy;
    x1_[i] = s.x[i] + half * s.vx[i];
    y1_[i] = s.y[i] + half * s.vy[i];
    vx1_[i] = s.vx[i] + half * avx;
    vy1_[i] = s.vy[i] + half * avy;
  }
  // Stages 2 and 3 at t + dt/2, stage 4 at t + dt.
  for (int stage = 2; stage <= 4; ++stage) {
    const double phase = stage == 4 ? phase_end : phase_half;
    smooth_acceleration(x1_.data(), y1_.data(), phase, s.jitter, ax_.data(), ay_.data());
    const double weight = stage == 4 ? 1.0 : 2.0;
    const double next = stage == 2 ? half : dt_; // step to the next stage's point
    for (int i = 0; i < n; ++i) {
      const double vx = vx1_[i];
      const double vy = vy1_[i];
      const double avx = ax_[i] - drag_ * vx;
      const double avy = ay_[i] - drag_ * vy;
      kx_[i] += weight * vx;
      ky_[i] += weight * vy;
      kvx_[i] += weight * avx;
      kvy_[i] += weight * avy;
      if (stage < 4) {
        x1_[i] = s.x[i] + next * vx;
        y1_[i] = s.y[i] + next * vy;
        vx1_[i] = s.vx[i] + next * avx;
        vy1_[i] = s.vy[i] + next * avy;
      }
    }
  }
  const double sixth = dt_ / 6.0;
  for (int i = 0; i < n; ++i) {
    const double x = s.x[i] + sixth * kx_[i];
    const double y = s.y[i] + sixth * ky_[i];
    const double vx = s.vx[i] + sixth * kvx_[i];
    const double vy = s.vy[i] + sixth * kvy_[i];
    finish_mass(s, i, s.x[i], s.y[i], x, y, vx, vy);
  }
  advance_wave(s);
}

} // namespace soda
