// TraceCsv: a per-frame trace of a running scene as CSV.
//
// One row per frame: frame, wave_phase, wave_mode (1 forward, -1 reverse, 0 manual,
// as in the golden traces of the original engine), then x, y, vx, vy of every free
// mass in file order. Numbers are shortest round-trip, so a trace holds the exact
// state and two traces can be compared bit for bit with a text diff.
#pragma once

#include <ostream>

#include "core/model.hpp"

namespace soda {

class TraceCsv {
 public:
  /// Writes the header row.
  TraceCsv(std::ostream& out, const Model& model);
  /// Writes one row for `state` (its frame counter is the row's frame).
  void write_row(const State& state);

 private:
  std::ostream& out_;
  int mass_count_;
};

} // namespace soda
