// A fused scene's masses in file order (force_ordered), and what the SIMD mass pass
// leaves to be done in mass order: autoreverse (replay_side_hits) and the fixed
// bars (bar_pass).
#include <algorithm>
#include <bit>

#include "core/fused/kernel_table.hpp"
#include "core/fused/sine_rows.hpp"
#include "core/physics_rules.hpp"

namespace soda::fused {

// Fixed bars: collide_with_fixed_bars for mass p of creature c (working index i)
// on the pair arrays, with its state's bar memory.
void SceneData::collide_with_bars(State& s, int c, int p, int i, const MassMove& move) {
  ++bar_rules_run;
  const Creature& cr = creatures[static_cast<std::size_t>(c)];
  rules::apply_fixed_bars(cr.model->fixed_bars, s.bar_memory, p, move, cr.bar_surface, px(i), py(i), pvx(i), pvy(i));
}

// Mass i's step from (x, y, vx, vy) (its working position and velocity before its
// impulses): the impulses in file order of the links, then rules::move_mass.
rules::MassStepResult SceneData::move_one_mass(const rules::MassConstants& k, int i, double& x, double& y,
                                               double& vx, double& vy) const {
  const std::uint32_t* sl = impulse_slots.data() + first_slot_of_mass[i];
  for (int r = 0; r < rounds_of_mass[i]; ++r, sl += kGatherGroup) {
    vx += impulses[*sl];
    vy += impulses[*sl + 1];
  }
  return rules::move_mass(k, x, y, vx, vy);
}

// Masses one by one in file order, exactly as step.cpp move_masses (single-model
// scenes; FastStepOptions::force_ordered).
void SceneData::ordered_masses(State& s) {
  const Model& m = *creatures[0].model;
  const rules::MassConstants k = rules::frame_constants(m);
  for (int p = 0; p < masses; ++p) {
    const int i = creatures[0].work_of_point[p];
    double xi = px(i), yi = py(i), vxi = pvx(i), vyi = pvy(i);
    const rules::MassStepResult moved = move_one_mass(k, i, xi, yi, vxi, vyi);
    pvx(i) = vxi;
    pvy(i) = vyi;
    if (!moved.moved) continue;
    rules::autoreverse_on_wall_hit(moved.hit, m.autoreverse, s.wave_mode, s.last_side_wall);
    px(i) = xi;
    py(i) = yi;
    if (!m.fixed_bars.empty()) collide_with_bars(s, 0, p, i, moved.move);
  }
}

namespace {
bool held_by_bars(const BarMemory& memory, int p) {
  if (static_cast<std::size_t>(p) < memory.corners.size() && memory.corners[static_cast<std::size_t>(p)].bar >= 0) {
    return true;
  }
  return std::any_of(memory.contacts.begin(), memory.contacts.end(), [p](const BarContact& c) { return c.mass == p; });
}
} // namespace

namespace {
void set_bit(std::vector<std::uint64_t>& bits, int p, bool on) {
  const std::uint64_t bit = std::uint64_t{1} << (p % 64);
  std::uint64_t& word = bits[static_cast<std::size_t>(p / 64)];
  word = on ? (word | bit) : (word & ~bit);
}
} // namespace

// Which masses a bar remembers or a corner holds, from each state's memory (a run
// may bring other states).
void SceneData::watch_bars(State* const* st) {
  std::fill(bar_held.begin(), bar_held.end(), 0);
  for (int c : bar_creatures) {
    const Creature& cr = creatures[static_cast<std::size_t>(c)];
    for (int p = 0; p < cr.model->mass_count; ++p) set_bit(bar_held, cr.mass_base + p, held_by_bars(st[c]->bar_memory, p));
  }
  move_start.assign(2 * static_cast<std::size_t>(padded_masses), 0.0);
  move_velocity.assign(2 * static_cast<std::size_t>(padded_masses), 0.0);
  bar_rules_mask = bar_scene_mask;
}

void SceneData::park(int c) {
  if (bar_rules_mask.empty()) return;
  const Creature& cr = creatures[static_cast<std::size_t>(c)];
  for (int p = 0; p < cr.model->mass_count; ++p) set_bit(bar_rules_mask, cr.mass_base + p, false);
}

// Fixed bars after the SIMD mass pass (which left every mass as the reference
// leaves it before its bar rules, autoreverse replayed, and kept each move), each
// creature's masses in file order as the reference meets them (creatures never
// interact, so their order among each other is free). The bar rules of a mass read
// and change only its own move and its own memory (its contacts and corner; the
// contact list's order follows the calls, which are the reference's but for calls
// that change nothing), so a mass that no bar remembers, no corner holds and whose
// move touches no bar's box (may_touch_bars, in the pass) is left as the pass left
// it. Until every mass of a creature has its corner entry all of them take the
// rules (the reference's first call makes it). The move is the one
// rules::move_mass makes: the end before the container is start + velocity, the
// rest test on that velocity.
void SceneData::bar_pass(State* const* st) {
  std::copy(bar_held.begin(), bar_held.end(), bar_due.begin());
  for (std::size_t b = 0; b < bar_touch.size(); ++b) {
    for (std::uint32_t lanes = bar_touch[b]; lanes != 0; lanes &= lanes - 1) {
      const int i = static_cast<int>(b) * W + kLaneLink(W, std::countr_zero(lanes));
      if (i < masses) set_bit(bar_due, file_of_work[static_cast<std::size_t>(i)], true);
    }
  }
  for (int c : bar_creatures) {
    const Creature& cr = creatures[static_cast<std::size_t>(c)];
    if (st[c]->bar_memory.corners.size() >= static_cast<std::size_t>(cr.model->mass_count)) continue;
    for (int p = 0; p < cr.model->mass_count; ++p) set_bit(bar_due, cr.mass_base + p, true);
  }
  for (std::size_t w = 0; w < bar_due.size(); ++w) {
    for (std::uint64_t due = bar_due[w] & bar_rules_mask[w]; due != 0; due &= due - 1) {
      const int g = static_cast<int>(w * 64) + std::countr_zero(due);
      const int c = creature_of_mass[static_cast<std::size_t>(g)];
      bar_rules(*st[c], c, g - creatures[static_cast<std::size_t>(c)].mass_base);
    }
  }
}

// The bar rules for mass p (file order) of creature c on its move of this frame;
// the mass then keeps the tile of where it is.
void SceneData::bar_rules(State& s, int c, int p) {
  const Creature& cr = creatures[static_cast<std::size_t>(c)];
  const std::size_t i = static_cast<std::size_t>(cr.work_of_point[static_cast<std::size_t>(p)]);
  const double vx = move_velocity[2 * i], vy = move_velocity[2 * i + 1];
  if (!rules::is_at_rest(vx, vy)) { // else not moved: no bar rules
    const double x0 = move_start[2 * i], y0 = move_start[2 * i + 1];
    collide_with_bars(s, c, p, static_cast<int>(i), rules::mass_move(x0, y0, x0 + vx, y0 + vy, vx, vy));
    set_bit(bar_held, cr.mass_base + p, held_by_bars(s.bar_memory, p));
  }
  keep_tile(static_cast<int>(i), px(static_cast<int>(i))); // where its next move starts
}

void SceneData::keep_tile(int i, double x) {
  double* to = mass_tile.data() + tile_at(i);
  if (x >= to[0] && x <= to[W]) return; // still in its tile
  const Model& m = *creatures[static_cast<std::size_t>(creature_of_mass[static_cast<std::size_t>(i)])].model;
  const double* tile = tile_of(m.fixed_bars, x);
  for (int v = 0; v < kTileValues; ++v) to[v * W] = tile[v];
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
