// Muscle targets from shared rows of sines: filling the rows (sine_rows.hpp has
// the per-frame half).
#include <algorithm>

#include "core/fused/kernel_table.hpp"
#include "core/fused/sine_rows.hpp"

namespace soda::fused {

// The wave states of the wave creatures (wave_state_of, wave_state_leader) and the distinct
// sine arguments of a row under them (first_argument_of_state, argument_muscle_phase, argument_of_group; muscle_argument),
// numbered state by state, in creature and group order within a state: where
// every creature has its own state, or all share one, and no argument is shared,
// argument g is group g and the targets read the sines by group.
void SceneData::number_arguments(State* const* st) {
  wave_states = 0;
  for (int c : wave_creatures) {
    int k = 0;
    while (k < wave_states && !same_wave(st, c, wave_state_leader[k])) ++k;
    wave_state_of[c] = k;
    if (k == wave_states) wave_state_leader[wave_states++] = c;
  }
  // State by state, so that the arguments of a state are consecutive (args_kernel).
  distinct_arguments = 0;
  for (int k = 0; k < wave_states; ++k) {
    first_argument_of_state[k] = distinct_arguments;
    for (int c : wave_creatures) {
      if (wave_state_of[c] != k) continue;
      const Creature& cr = creatures[c];
      for (int g = cr.group_base; g < cr.group_base + cr.groups; ++g) {
        const int key = k * muscle_phases + muscle_phase_of_group[g];
        if (argument_of_key[key] < 0) {
          argument_of_key[key] = distinct_arguments;
          key_of_argument[distinct_arguments] = key;
          argument_muscle_phase[distinct_arguments++] = group_phase[g];
        }
        argument_of_group[g] = argument_of_key[key];
      }
    }
  }
  first_argument_of_state[wave_states] = distinct_arguments;
  for (int d = 0; d < distinct_arguments; ++d) argument_of_key[key_of_argument[d]] = -1;
  // Where the targets read (see sine_rows): by group where argument g is group g.
  bool remap = false;
  for (int g = 0; g < groups; ++g) remap = remap || argument_of_group[g] != g;
  // Remapped sines in registers are copied out by group per fill (group_sines).
  const bool read_distinct = remap && !sines_in_registers;
  if (read_distinct) {
    for (int q = 0; q < padded_wave_muscles; ++q) muscle_argument_lane[q] = muscle_argument[q] = argument_of_group[muscle_group[q]];
  }
  sine_rows = remap && sines_in_registers ? group_sines.data() : argument_sines.data();
  sine_stride = read_distinct ? distinct_arguments : groups;
  sine_index = read_distinct ? muscle_argument.data() : muscle_group.data();
  sine_lane = read_distinct ? muscle_argument_lane.data() : muscle_group_lane.data();
  numbering_valid = true;
}

// Sines for this frame and the next rows - 1 (while each wave's direction holds),
// for every creature, in one batch. Row 0 is the current phase.
//
// Creatures whose waves are in the same state (a GA population shares most genes)
// get the same rows of phases, computed once, and each distinct (wave state,
// muscle phase) pair gives one sine argument whatever the number of creatures and
// muscles sharing it: the same operations on the same bits give the same sine.
// The states are those of the last fill while every creature is still in its
// state's (its leader's): waves move in step until a direction changes, so the
// numbering of the arguments is kept from fill to fill (two states that come to
// agree stay apart until then: exact, only not shared).
void SceneData::fill_rows(State* const* st) {
  bool same_states = numbering_valid;
  for (std::size_t k = 0; k < wave_creatures.size() && same_states; ++k) {
    const int c = wave_creatures[k];
    same_states = same_wave(st, c, wave_state_leader[wave_state_of[c]]);
  }
  if (!same_states) number_arguments(st);
  // Each state's rows of phases and the advance from the last (rules::advance_wave_phase).
  const std::size_t stride = creatures.size();
  bool all_standing = true;
  for (int k = 0; k < wave_states; ++k) {
    const int c = wave_state_leader[k];
    double phase = st[c]->wave_phase;
    const WaveDirection mode = st[c]->wave_mode;
    const double speed = creatures[c].model->wave_speed;
    row_phase[k] = phase;
    for (int r = 1; r <= rows_per_fill; ++r) {
      const double next = rules::advance_wave_phase(phase, speed, mode);
      row_phase[r * stride + k] = next;
      all_standing = all_standing && bits_of(next) == bits_of(phase);
      phase = next;
    }
  }
  for (int c : wave_creatures) creatures[c].rows_mode = st[c]->wave_mode;
  rows_standing = all_standing;
  // Every wave stands still (manual mode, speed 0): one row of sines serves all.
  const int filled = all_standing ? 1 : rows_per_fill;
  args_fn(simd)(*this, filled);
  const int n = filled * distinct_arguments;
  sine_fn(arguments.data(), argument_sines.data(), n);
  sines_evaluated += n;
  jitter_sines(st, filled);
  if (sine_rows == group_sines.data()) { // remapped, by group
    for (int r = 0; r < filled; ++r) {
      const double* from = argument_sines.data() + static_cast<std::size_t>(r) * distinct_arguments;
      double* to = group_sines.data() + static_cast<std::size_t>(r) * groups;
      for (int g = 0; g < groups; ++g) to[g] = from[argument_of_group[g]];
    }
  }
  for (int r = filled; r < rows_per_fill; ++r) {
    std::copy(sine_rows, sine_rows + sine_stride, sine_rows + static_cast<std::size_t>(r) * sine_stride);
  }
  row_count = rows_per_fill;
  row_next = 0;
}

// The sines of each wave state whose creatures carry sine jitter, moved as
// rules::muscle_sine moves them, from the same arguments. Creatures with
// different jitter never share a wave state (same_wave), so a state's one
// jitter is its leader's.
void SceneData::jitter_sines(State* const* st, int filled) {
  for (int k = 0; k < wave_states; ++k) {
    const PreparedJitter jitter(st[wave_state_leader[k]]->jitter);
    if (jitter.threshold == 0) continue;
    for (int r = 0; r < filled; ++r) {
      const std::size_t row = static_cast<std::size_t>(r) * distinct_arguments;
      for (int d = first_argument_of_state[k]; d < first_argument_of_state[k + 1]; ++d) {
        argument_sines[row + d] = jitter.apply(argument_sines[row + d], arguments[row + d]);
      }
    }
  }
}

} // namespace soda::fused
