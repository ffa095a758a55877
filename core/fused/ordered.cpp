// A fused scene's masses in file order (with fixed bars: the bar rules need each
// move before the container's response), and what the SIMD mass pass leaves to be
// done in mass order: autoreverse (replay_side_hits).
#include "core/fused/kernel_table.hpp"
#include "core/fused/sine_rows.hpp"
#include "core/physics_rules.hpp"

namespace soda::fused {

// Fixed bars (single-model scenes): collide_with_fixed_bars for mass p (working
// index i) on the pair arrays, with the state's bar memory.
void SceneData::collide_with_bars(State& s, int p, int i, const MassMove& move) {
  const Model& m = *creatures[0].model;
  MassMove clamped = move;
  clamped.x = px(i);
  clamped.y = py(i);
  MassEnd end;
  const Surface surface{m.surface_friction, m.surface_reflection, m.width, m.height};
  if (!collide_with_fixed_bars(m.fixed_bars, s.bar_memory, p, clamped, surface, end)) return;
  px(i) = end.x;
  py(i) = end.y;
  pvx(i) = end.vx;
  pvy(i) = end.vy;
}

// Masses one by one in file order, exactly as step.cpp move_masses (single-model
// scenes; used whenever there are fixed bars).
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
    if (!bar_a.empty()) collide_with_bars(s, p, i, moved.move);
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
