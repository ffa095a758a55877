#include "analytic_scenes.hpp"

#include <cmath>

namespace sodaevo::bench {

soda::ModelDef open_world(double gravity, double friction, double springyness) {
  soda::ModelDef def;
  def.width = 100000;
  def.height = 100000;
  def.environment = {gravity, friction, springyness};
  def.settings.autoreverse = false;
  return def;
}

namespace {

soda::NodeDef mass(const std::string& id, double x, double y, double vx = 0.0, double vy = 0.0) {
  return {id, false, x, y, vx, vy};
}

} // namespace

AnalyticScene free_fall_with_friction() {
  const double g = 0.3, f = 0.05, x0 = 500.0, y0 = 2000.0;
  AnalyticScene s;
  s.name = "free fall with friction";
  s.def = open_world(g, f, 0.2);
  s.def.nodes.push_back(mass("m0", x0, y0));
  s.exact = [=](double t) {
    const double lambda = -std::log1p(-f);
    const double v_inf = -g / lambda;
    const double decay = -std::expm1(-lambda * t); // 1 - e^(-lambda t), accurate for small t
    return std::vector<double>{x0, y0 + v_inf * (t - decay / lambda)};
  };
  return s;
}

AnalyticScene single_spring() {
  const double k = 0.2, rest = 100.0, e0 = 10.0, xc = 500.0, y0 = 200.0, vy = 1.0;
  AnalyticScene s;
  s.name = "single spring";
  s.def = open_world(0.0, 0.0, k);
  s.def.nodes.push_back(mass("m0", xc - (rest + e0) / 2.0, y0, 0.0, vy));
  s.def.nodes.push_back(mass("m1", xc + (rest + e0) / 2.0, y0, 0.0, vy));
  s.def.links.push_back({soda::LinkKind::Spring, 0, 1, rest, 0.0, 0.0});
  s.exact = [=](double t) {
    const double half = (rest + e0 * std::cos(std::sqrt(2.0 * k) * t)) / 2.0;
    const double y = y0 + vy * t;
    return std::vector<double>{xc - half, y, xc + half, y};
  };
  return s;
}

AnalyticScene pendulum_chain() {
  AnalyticScene s;
  s.name = "pendulum chain";
  s.def = open_world(0.3, 0.01, 0.2);
  s.def.wave = {0.5, 0.0, 0.02};
  s.def.nodes.push_back({"top", true, 500.0, 800.0, 0.0, 0.0});
  const double step = 40.0 / std::sqrt(2.0);
  for (int i = 1; i <= 4; ++i) s.def.nodes.push_back(mass("m" + std::to_string(i), 500.0 + i * step, 800.0 - i * step));
  for (int i = 0; i < 4; ++i) {
    const bool muscle = i == 2;
    s.def.links.push_back({muscle ? soda::LinkKind::Muscle : soda::LinkKind::Spring, i, i + 1, 40.0,
                           muscle ? 0.5 : 0.0, muscle ? 0.25 : 0.0});
  }
  return s;
}

AnalyticScene stiff_hub() {
  const double k = 0.5, f = 0.05, x0 = 2.0, centre = 500.0, y = 500.0;
  const int parallel = 6;
  AnalyticScene s;
  s.name = "stiff hub";
  s.def = open_world(0.0, f, k);
  s.def.nodes.push_back(mass("m", centre + x0, y));
  s.def.nodes.push_back({"left", true, centre - 100.0, y, 0.0, 0.0});
  s.def.nodes.push_back({"right", true, centre + 100.0, y, 0.0, 0.0});
  for (int i = 0; i < parallel; ++i) {
    s.def.links.push_back({soda::LinkKind::Spring, 1, 0, 100.0, 0.0, 0.0});
    s.def.links.push_back({soda::LinkKind::Spring, 0, 2, 100.0, 0.0, 0.0});
  }
  s.exact = [=](double t) {
    const double lambda = -std::log1p(-f);
    const double w2 = 2.0 * parallel * k;
    const double wd = std::sqrt(w2 - lambda * lambda / 4.0);
    const double x = x0 * std::exp(-lambda * t / 2.0) * (std::cos(wd * t) + lambda / (2.0 * wd) * std::sin(wd * t));
    return std::vector<double>{centre + x, y};
  };
  return s;
}

std::vector<AnalyticScene> analytic_scenes() {
  return {free_fall_with_friction(), single_spring(), pendulum_chain(), stiff_hub()};
}

} // namespace sodaevo::bench
