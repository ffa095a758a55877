// A fused scene's masses in file order, and what the SIMD mass pass leaves to be
// done in mass order: autoreverse (replay_side_hits) and fixed bars (bars_pass).
#include "core/fused/kernel_table.hpp"
#include "core/fused/sine_rows.hpp"
#include "core/physics_rules.hpp"

namespace soda::fused {

// Fixed bars (single-model scenes): rules::collide_with_bars on the pair arrays
// (x at even, y at odd offsets; bar ends and the mass as doubled indices).
void SceneData::collide_with_bars(int i, double x0, double y0) {
  const Model& m = *creatures[0].model;
  rules::collide_with_bars(positions.data(), positions.data() + 1, bar_a.data(), bar_b.data(), static_cast<int>(bar_a.size()),
                           2 * i, x0, y0, px(i), py(i), pvx(i), pvy(i), m.surface_friction, m.surface_reflection);
}

// Masses one by one in file order, exactly as step.cpp move_masses (single-model
// scenes; used when a bar has a free-mass end: a mass's bar test then sees the
// masses moved before it).
void SceneData::ordered_masses(State& s) {
  const Model& m = *creatures[0].model;
  const rules::MassConstants k = rules::frame_constants(m);
  for (int p = 0; p < masses; ++p) {
    const int i = creatures[0].work_of_point[p];
    // Impulses in file order of the links.
    double vxi = pvx(i), vyi = pvy(i);
    const std::uint32_t* sl = impulse_slots.data() + first_slot_of_mass[i];
    for (int r = 0; r < rounds_of_mass[i]; ++r, sl += kGatherGroup) {
      vxi += impulses[*sl];
      vyi += impulses[*sl + 1];
    }
    double xi = px(i), yi = py(i);
    const rules::MassStepResult moved = rules::move_mass(k, xi, yi, vxi, vyi);
    pvx(i) = vxi;
    pvy(i) = vyi;
    if (!moved.moved) continue;
    rules::autoreverse_on_wall_hit(moved.hit, m.autoreverse, s.wave_mode, s.last_side_wall);
    px(i) = xi;
    py(i) = yi;
    if (!bar_a.empty()) collide_with_bars(i, moved.x0, moved.y0);
  }
}

// Autoreverse (rules::autoreverse_on_wall_hit) for the side-wall hits of this
// frame, per creature in its mass order as the reference meets them.
void SceneData::replay_side_hits(State* const* st) {
  leave_rows(); // a direction may change
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    for (int p = 0; p < cr.model->mass_count; ++p) {
      double* hit = side_hit.data() + 2 * static_cast<std::size_t>(cr.work_of_point[p]); // twice the same value
      const double h = hit[0];
      hit[0] = hit[1] = 0.0;
      if (h != 0.0) {
        rules::autoreverse_on_wall_hit(h < 0.0 ? SideWall::Left : SideWall::Right, cr.model->autoreverse,
                                       st[c]->wave_mode, st[c]->last_side_wall);
      }
    }
  }
}

// Bars whose ends are fixed nodes: each mass independent of the others, so the bar
// tests can follow the SIMD container step, in mass order.
void SceneData::bars_pass() {
  for (int p = 0; p < masses; ++p) {
    const int i = creatures[0].work_of_point[p];
    collide_with_bars(i, positions_before_move[2 * i], positions_before_move[2 * i + 1]);
  }
}

void SceneData::ordered_frame(State& s) {
  State* const st[1] = {&s};
  if (wave_muscles > 0) update_targets(st);
  if (link_slots > 0) link_fn(simd)(*this);
  const WaveDirection mode = s.wave_mode;
  ordered_masses(s);
  if (s.wave_mode != mode) leave_rows();
  advance_waves(st);
}

} // namespace soda::fused
