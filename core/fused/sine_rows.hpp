// Muscle targets from shared rows of sines: the inline half (per frame).
//
// rules::muscle_target_length is split in two so that a sine is shared: sine =
// sin(2pi*(phi_m - phi_w)) once per distinct (wave state, muscle phase) pair, then
// per muscle rest * (1 + (Aw*Am) * sine), the same operations in the same order.
// The sines of the next frames are computed in one batch (fill_rows, sine_rows.cpp)
// for the phases the waves will have if their directions hold; a row is used only
// while every creature's phase is the row's, bit for bit.
#pragma once

#include "core/detail/bits.hpp"
#include "core/fused/scene_data.hpp"
#include "core/physics_rules.hpp"

namespace soda::fused {

// Muscle targets: rules::muscle_target_length split in two so that the sine is
// shared, sine = sin(2pi*(phi_m - phi_w)) once per distinct phase per creature,
// then per muscle rest * (1 + (Aw*Am) * sine) with the same operations in the same
// order (targets_kernel). row_for_frame returns this frame's row of sines, filling
// the rows when the waves left them, or nullptr when no wave moved (the targets
// stand). Always inlined, so that the frame in registers (register_chunk) calls nothing
// but fill_rows: a call spills every vector register.
inline const double* SceneData::row_for_frame(State* const* st) {
  if (rows_synced && row_next < row_count) {
    if (rows_standing && targets_valid) return nullptr;
    current_row = row_next++;
    targets_valid = true;
    return sine_rows + static_cast<std::size_t>(current_row) * sine_stride;
  }
  leave_rows(); // the rows ran out: targets_phase_bits must say what the targets are for
  bool changed = !targets_valid;
  for (std::size_t k = 0; k < wave_creatures.size() && !changed; ++k) {
    const int c = wave_creatures[k];
    changed = bits_of(st[c]->wave_phase) != creatures[c].targets_phase_bits;
  }
  if (!changed) return nullptr;
  bool row_usable = row_next < row_count;
  for (std::size_t k = 0; k < wave_creatures.size() && row_usable; ++k) {
    const int c = wave_creatures[k];
    row_usable = bits_of(st[c]->wave_phase) == bits_of(row_phase[row_at(c, row_next)]) &&
                 st[c]->wave_mode == creatures[c].rows_mode;
  }
  if (!row_usable) fill_rows(st);
  current_row = row_next++;
  targets_valid = true;
  rows_synced = true;
  return sine_rows + static_cast<std::size_t>(current_row) * sine_stride;
}
/// Index of wave creature c's phase in row r of row_phase (its advance: row r + 1).
inline std::size_t SceneData::row_at(int c, int r) const {
  return static_cast<std::size_t>(r) * creatures.size() + static_cast<std::size_t>(wave_state_of[c]);
}
/// Whether creatures a and b have their waves in the same state (phase and speed
/// bit for bit, same direction) and the same sine jitter: the same rows of phases
/// and of sines.
inline bool SceneData::same_wave(State* const* st, int a, int b) const {
  return bits_of(st[a]->wave_phase) == bits_of(st[b]->wave_phase) && st[a]->wave_mode == st[b]->wave_mode &&
         bits_of(creatures[a].model->wave_speed) == bits_of(creatures[b].model->wave_speed) &&
         st[a]->jitter == st[b]->jitter;
}
/// Ends rows_synced (see there), noting the phases the targets are for.
inline void SceneData::leave_rows() {
  if (!rows_synced) return;
  rows_synced = false;
  for (int c : wave_creatures) creatures[c].targets_phase_bits = bits_of(row_phase[row_at(c, current_row)]);
}
// The wave advance of this frame: already computed for the current row (same
// rule, same inputs) when the phase and direction are still the row's.
inline double SceneData::advance_phase(int c, const State& st) const {
  const Creature& cr = creatures[c];
  if (current_row >= 0 && cr.groups > 0) {
    const std::size_t at = row_at(c, current_row);
    if (bits_of(st.wave_phase) == bits_of(row_phase[at]) && st.wave_mode == cr.rows_mode) {
      return row_phase[row_at(c, current_row + 1)];
    }
  }
  return rules::advance_wave_phase(st.wave_phase, cr.model->wave_speed, st.wave_mode);
}
inline void SceneData::advance_waves(State* const* st) {
  if (rows_synced) {
    for (int c : wave_creatures) st[c]->wave_phase = row_phase[row_at(c, current_row + 1)];
    for (int c : still_creatures) {
      st[c]->wave_phase = rules::advance_wave_phase(st[c]->wave_phase, creatures[c].model->wave_speed, st[c]->wave_mode);
    }
    return;
  }
  for (std::size_t c = 0; c < creatures.size(); ++c) st[c]->wave_phase = advance_phase(static_cast<int>(c), *st[c]);
}

} // namespace soda::fused
