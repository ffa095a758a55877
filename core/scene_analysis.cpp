#include "scene_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>

#include "detail/bits.hpp"

namespace soda {

namespace {

long long frames_for_distance(double distance) {
  if (!(distance >= 0.0)) return 0; // negative or NaN: may be hit at once
  const double frames = std::floor(distance / kMaxMovePerFrame);
  return frames >= static_cast<double>(kSafeFramesCap) ? kSafeFramesCap : static_cast<long long>(frames);
}

} // namespace

WallSafeFrames wall_safe_frames(const Model& model, const double* x, const double* y, long stride) {
  if (model.mass_count == 0) return {kSafeFramesCap, kSafeFramesCap, kSafeFramesCap};
  double min_x = x[0], max_x = x[0], min_y = y[0], max_y = y[0];
  bool sane = true;
  for (int i = 0; i < model.mass_count; ++i) {
    const double xi = x[i * stride], yi = y[i * stride];
    // The negated form is also false for NaN.
    sane = sane && std::fabs(xi) <= kWallAnalysisMaxCoordinate && std::fabs(yi) <= kWallAnalysisMaxCoordinate;
    min_x = std::min(min_x, xi);
    max_x = std::max(max_x, xi);
    min_y = std::min(min_y, yi);
    max_y = std::max(max_y, yi);
  }
  if (!sane) return {};
  WallSafeFrames s;
  s.floor = frames_for_distance(min_y);
  s.ceiling = frames_for_distance(model.height - max_y);
  s.sides = std::min(frames_for_distance(min_x), frames_for_distance(model.width - max_x));
  return s;
}

WallNeeds walls_within(const Model& model, const double* x, const double* y, long long frames) {
  const WallSafeFrames s = wall_safe_frames(model, x, y);
  return {s.floor < frames, s.ceiling < frames, s.sides < frames};
}

SceneNeeds analyse_scene(const Model& model, long long frame_budget) {
  SceneNeeds n;
  n.frame_budget = frame_budget;
  n.masses = model.mass_count;
  n.links = model.link_count();
  std::set<std::uint64_t> phases;
  for (int i = 0; i < model.link_count(); ++i) {
    if (model.is_mass(model.link_a[i]) || model.is_mass(model.link_b[i])) ++n.active_links;
    if (!model.link_muscle[i]) continue;
    ++n.muscles;
    // Power +-0 makes the target rest*(1 + +-0) = rest exactly: a spring.
    if (!is_wave_muscle(model, i)) continue;
    if (!(model.is_mass(model.link_a[i]) || model.is_mass(model.link_b[i]))) continue;
    ++n.wave_muscles;
    phases.insert(bits_of(model.link_phase[i]));
  }
  n.distinct_phases = static_cast<int>(phases.size());
  n.wave = n.wave_muscles > 0;
  n.gravity = bits_of(model.gravity_step) != bits_of(0.0);
  if (model.bar_count() > 0) {
    n.bars = BarKind::FixedSegments;
    for (int b = 0; b < model.bar_count(); ++b) {
      if (model.is_mass(model.bar_a[b]) || model.is_mass(model.bar_b[b])) n.bars = BarKind::MovingEnds;
    }
  }
  n.autoreverse = model.autoreverse && model.wave_direction0 != WaveDirection::Manual;
  // With bars the push-off after a bar response is not bounded by the speed
  // limit, so every wall is kept.
  if (n.bars == BarKind::None) n.walls = walls_within(model, model.x0.data(), model.y0.data(), frame_budget);
  return n;
}

std::string SceneNeeds::describe() const {
  std::string s;
  s += std::to_string(masses) + " masses, " + std::to_string(active_links) + "/" + std::to_string(links) + " links;";
  if (wave) {
    s += " wave(" + std::to_string(wave_muscles) + " muscles, " + std::to_string(distinct_phases) + " sines)";
  } else {
    s += " no-wave";
  }
  s += gravity ? " gravity" : " no-gravity";
  s += " walls:";
  if (walls.floor) s += "floor,";
  if (walls.ceiling) s += "ceiling,";
  if (walls.sides) s += "sides,";
  if (!walls.floor && !walls.ceiling && !walls.sides) s += "none,";
  s.pop_back();
  s += bars == BarKind::None ? " bars:none" : bars == BarKind::FixedSegments ? " bars:fixed" : " bars:moving";
  s += autoreverse ? " autoreverse" : "";
  s += " (budget " + std::to_string(frame_budget) + " frames)";
  return s;
}

} // namespace soda
