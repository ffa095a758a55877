#include "bench/baselines.hpp"

#include <cmath>
#include <stdexcept>

#include "core/physics_rules.hpp"

namespace sodaevo::bench {

// ---------------------------------------------------------------------------
// Seed paper, Algorithm 1-2.
// ---------------------------------------------------------------------------

struct SeedBaseline::Mass {
  double x = 0, y = 0;   // position
  double vx = 0, vy = 0; // velocity
  double fx = 0, fy = 0; // force accumulator
  double m = 1.0;        // mass
  bool fixed = false;
};

struct SeedBaseline::Spring {
  Mass* v1 = nullptr;
  Mass* v2 = nullptr;
  double k = 0;     // spring constant
  double d = 0;     // rest length
  double am = 0;    // muscle amplitude
  double phase = 0; // muscle phase (cycles)
};

SeedBaseline::SeedBaseline(const soda::Model& model) : model_(&model) {
  for (int p = 0; p < model.point_count; ++p) {
    auto mass = std::make_unique<Mass>();
    mass->fixed = !model.is_mass(p);
    masses_.push_back(std::move(mass));
  }
  for (int i = 0; i < model.link_count(); ++i) {
    auto s = std::make_unique<Spring>();
    s->v1 = masses_[model.link_a[i]].get();
    s->v2 = masses_[model.link_b[i]].get();
    s->k = model.springyness;
    s->d = model.link_rest[i];
    s->am = model.link_amplitude[i];
    s->phase = model.link_phase[i];
    (model.link_muscle[i] ? muscles_ : springs_).push_back(std::move(s));
  }
  reset();
}

SeedBaseline::~SeedBaseline() = default;

void SeedBaseline::reset() {
  for (int p = 0; p < model_->point_count; ++p) {
    Mass& m = *masses_[p];
    m.x = model_->x0[p];
    m.y = model_->y0[p];
    m.vx = model_->vx0[p];
    m.vy = model_->vy0[p];
    m.fx = m.fy = 0;
  }
  wave_angle_ = 2.0 * M_PI * model_->wave_phase0;
}

namespace {

// Algorithm 1, lines 3-12, for one spring of current target length `rest`.
inline void apply_spring(SeedBaseline::Mass& m1, SeedBaseline::Mass& m2, double k, double rest) {
  const double ddx = m1.x - m2.x;
  const double ddy = m1.y - m2.y;
  double d = std::sqrt(ddx * ddx + ddy * ddy);
  if (d == 0.0) return; // no direction
  d = d - rest;
  // The paper writes atan(dx/dy); taken literally the direction flips when dy < 0
  // and the creature explodes, so the quadrant is restored (still one atan).
  double theta = std::atan(ddx / ddy);
  if (ddy < 0) theta += M_PI;
  m1.fx = m1.fx - k * d * std::sin(theta);
  m1.fy = m1.fy - k * d * std::cos(theta);
  m2.fx = m2.fx + k * d * std::sin(theta);
  m2.fy = m2.fy + k * d * std::cos(theta);
}

} // namespace

void SeedBaseline::run(long long frames) {
  const soda::Model& md = *model_;
  const double gravity = -md.gravity * static_cast<double>(static_cast<int>(md.gravity_direction));
  const double friction = 1.0 - md.friction;
  const double bounce = md.surface_reflection;
  for (long long f = 0; f < frames; ++f) {
    // Algorithm 1: springs, then muscles (target from the wave), then the wave.
    for (auto& s : springs_) apply_spring(*s->v1, *s->v2, s->k, s->d);
    for (auto& s : muscles_) {
      const double target = s->d * (1.0 + s->am * md.wave_amplitude * std::cos(wave_angle_ + 2.0 * M_PI * s->phase));
      apply_spring(*s->v1, *s->v2, s->k, target);
    }
    wave_angle_ = wave_angle_ + 2.0 * M_PI * md.wave_speed;
    // Algorithm 2: each mass object.
    for (auto& mp : masses_) {
      Mass& m = *mp;
      if (m.fixed) {
        m.fx = m.fy = 0;
        continue;
      }
      m.vx = m.vx + (0.0 + m.fx) / m.m;
      m.vy = m.vy + (gravity + m.fy) / m.m;
      m.x = m.x + m.vx;
      m.y = m.y + m.vy;
      m.fx = 0;
      m.fy = 0;
      m.vx = m.vx * friction;
      m.vy = m.vy * friction;
      // Boundary conditions with a bounce factor.
      if (m.y < 0) {
        m.y = 0;
        m.vy = m.vy * bounce;
      } else if (m.y > md.height) {
        m.y = md.height;
        m.vy = m.vy * bounce;
      }
      if (m.x < 0) {
        m.x = 0;
        m.vx = m.vx * bounce;
      } else if (m.x > md.width) {
        m.x = md.width;
        m.vx = m.vx * bounce;
      }
    }
  }
}

double SeedBaseline::checksum() const {
  double s = 0;
  for (const auto& m : masses_) s += m->x + m->y;
  return s;
}

// ---------------------------------------------------------------------------
// Plain loop of the exact rules.
// ---------------------------------------------------------------------------

PlainLoop::PlainLoop(const soda::Model& model) : model_(&model) {
  if (model.bar_count() > 0) throw std::invalid_argument("PlainLoop: models with fixed bars are not supported");
  nodes_.resize(static_cast<std::size_t>(model.point_count));
  for (int p = 0; p < model.point_count; ++p) nodes_[p].fixed = !model.is_mass(p);
  for (int i = 0; i < model.link_count(); ++i) {
    links_.push_back({model.link_muscle[i] ? Kind::Muscle : Kind::Spring, model.link_a[i], model.link_b[i],
                      model.link_rest[i], model.link_amplitude[i], model.link_phase[i]});
  }
}

void PlainLoop::step(soda::State& s) {
  namespace rules = soda::rules;
  const soda::Model& m = *model_;
  for (const Link& link : links_) {
    if (link.kind == Kind::FixedBar) continue;
    Node& a = nodes_[link.a];
    Node& b = nodes_[link.b];
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0.0) continue;
    double target = link.rest;
    if (link.kind == Kind::Muscle) {
      target = rules::muscle_target_length(link.rest, m.wave_amplitude, link.amplitude, link.phase, s.wave_phase,
                                            soda::SineJitter{});
    }
    const double c = rules::link_impulse_factor(m.springyness, length, target);
    if (!a.fixed) {
      a.vx += c * dx;
      a.vy += c * dy;
    }
    if (!b.fixed) {
      b.vx -= c * dx;
      b.vy -= c * dy;
    }
  }
  for (Node& n : nodes_) {
    if (n.fixed) continue;
    double vx = n.vx;
    double vy = rules::apply_gravity(n.vy, m.gravity, m.gravity_direction);
    const double factor = rules::friction_factor(vx, vy, m.friction);
    vx = factor * vx;
    vy = factor * vy;
    if (rules::is_at_rest(vx, vy)) {
      n.vx = vx;
      n.vy = vy;
      continue;
    }
    double x = n.x + vx;
    double y = n.y + vy;
    const soda::SideWall hit =
        rules::collide_with_container(x, y, vx, vy, m.width, m.height, m.surface_friction, m.surface_reflection);
    rules::autoreverse_on_wall_hit(hit, m.autoreverse, s.wave_mode, s.last_side_wall);
    n.x = x;
    n.y = y;
    n.vx = vx;
    n.vy = vy;
  }
  s.wave_phase = rules::advance_wave_phase(s.wave_phase, m.wave_speed, s.wave_mode);
}

void PlainLoop::run(soda::State& s, long long frames) {
  for (int p = 0; p < model_->point_count; ++p) nodes_[p] = {s.x[p], s.y[p], s.vx[p], s.vy[p], nodes_[p].fixed};
  for (long long f = 0; f < frames; ++f) step(s);
  for (int p = 0; p < model_->point_count; ++p) {
    s.x[p] = nodes_[p].x;
    s.y[p] = nodes_[p].y;
    s.vx[p] = nodes_[p].vx;
    s.vy[p] = nodes_[p].vy;
  }
  s.frame += frames;
}

} // namespace sodaevo::bench
