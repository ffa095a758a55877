// Fixed bars (terrain): the original engine's collision rules, exact to the last
// bit (docs/physics.md, "Fixed bars" and "The last bits").
//
// Split as Model/State (MuJoCo): FixedBars is constant (each bar's geometry, taken
// once from the positions at the first update, its chain neighbours, an index by x),
// built with the Model; BarMemory is dynamic and lives in the State (each bar's
// memory of the masses lying on it, and each mass's corner). A stepper calls
// collide_with_fixed_bars once per moving mass, after the container clamp.
//
// The two originals differ in one place only, the box pre-test of a bar: the 2003
// SodaConstructor engine normalises a bar's box, the 2004 racer's copy takes
// [x1, x1 + w] x [y1, y1 + h] as is, with the move's range widened by 0.01 on an
// inverted axis (so it lets creatures fall through bars that run downhill or right
// to left). BarEngine names the rule; there is no silent default:
// every Model says which one it steps with, and the outputs name it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "detail/aligned_vector.hpp"

namespace soda {

/// Which original's box test the fixed bars follow.
enum class BarEngine : std::uint8_t {
  SodaConstructor2003, ///< simulator.jar (2003): normalised bar box
  Racer2004,           ///< the racer's copy (easysoda.jar, 2004): box taken as is
                       ///< (docs/physics.md, "The last bits")
};
std::string bar_engine_name(BarEngine engine); ///< "2003" | "2004"
/// "2003" or "2004"; false for anything else.
bool parse_bar_engine(const std::string& text, BarEngine& engine);

/// Which side a bar takes for s0, the side a mass it remembers comes from
/// (docs/physics.md, "Inferred rules").
enum class SideRule : std::uint8_t {
  Stored, ///< always the remembered side (no tolerance; for the diagnosis)
  /// The remembered side only while the move starts within kSideTolerance of the
  /// bar's line, else the side of the start: the default. Inferred from one race
  /// (walker_313 on TerrainAi, frame 6763: a move starting 2.68 px off bar 1's line,
  /// remembered on side 0, ends on the side it started on; the original lets it
  /// go) and bounded only by it and the golden sets: any tolerance from 1e-11 to
  /// 2.6 px keeps every golden set and that race, 3e-12 or 2.7 px do not.
  Near,
};
/// The distance from a bar's line within which SideRule::Near keeps the remembered side.
inline constexpr double kSideTolerance = 1e-4;

/// The margin around a bar's box within which the crossing point of a remembered
/// mass's move still hits (docs/physics.md, "Inferred rules"). Inferred: a 1-ulp
/// case needs some margin (any >= 1e-9 fits it); walker_514 on TerrainAi (frame 6457: a
/// crossing point 9.35e-5 px beyond bar 0's end is no hit in the original) bounds
/// it below 9.3486e-5, so 1e-4 (the original code's FixedBar.TWEAK) is too wide.
inline constexpr double kHitMargin = 1e-5;
/// The margin of FixedBar.TWEAK, which walker_514 refutes; for the diagnosis of near-end misses.
inline constexpr double kTweakMargin = 1e-4;

/// One bar's constant geometry: from a to b, as the engine takes it once.
struct FixedBar {
  int a = 0, b = 0;                 ///< point indices of the ends (chain identity)
  double x1 = 0, y1 = 0, x2 = 0, y2 = 0;
  double w = 0, h = 0;              ///< x2 - x1, y2 - y1
  double length = 0;                ///< sqrt(w*w + h*h)
  double ux = 0, uy = 0;            ///< w/length, h/length
  double box_x0 = 0, box_x1 = 0, box_y0 = 0, box_y1 = 0; ///< normalised box of (x1, x1 + w), (y1, y1 + h)
  int next = -1, prev = -1;         ///< chain neighbours at b and at a (bar index)
  bool next_reversed = false;       ///< the next bar ends (not starts) at b
  bool prev_reversed = false;       ///< the previous bar starts (not ends) at a
};

/// The rules inferred from the golden races (docs/physics.md, "Inferred rules") as
/// switches. They exist for the refutation tests (tests/test_races_inferred.cpp),
/// which switch each to the alternative the golden races refute and watch the
/// golden result go; every Model steps with these defaults. Kept apart from the
/// bars' geometry, as Box2D keeps its test toggles apart from its bodies.
struct InferredBarRules {
  SideRule side_rule = SideRule::Near;
  double hit_margin = kHitMargin; ///< kTweakMargin: FixedBar.TWEAK's margin
  /// A concave joint whose end point projects past the far end of the next bar c:
  /// the mass is put at that end and caught in the corner there (c and its
  /// neighbour at that end), as in the corner it came into; false: put on c's line
  /// beyond the end (the joint rule read literally). Inferred from one race
  /// (walker_382 on TerrainAi, frame 3307) and bounded only by it.
  bool far_end_corner = true;
};

/// The bars of a model: geometry, chains and an index of bars by x (so a mass tests
/// only the bars whose x range its move reaches: terrains are 100,000 px wide).
struct FixedBars {
  BarEngine engine = BarEngine::SodaConstructor2003;
  InferredBarRules inferred; ///< the defaults, but in the refutation tests
  std::vector<FixedBar> bars; ///< link order
  // Index by x: cells of cell_width px from cell_x0; cell c holds the bars whose
  // normalised x range touches it, in link order (cell_start[c] .. cell_start[c+1]).
  double cell_x0 = 0.0;
  double cell_width = kMinCellWidth; ///< a power of two, so that x * cell_scale is x / cell_width exactly
  double cell_scale = 1.0 / kMinCellWidth;
  int cell_count = 0;
  std::vector<int> cell_start;
  std::vector<int> cell_bars;
  /// [kTileStride * cell_count] per cell c its tile, for a cheap test of whether a
  /// move may touch a bar (move_may_touch_bars): the tile's x range [x_lo, x_hi]
  /// (cell c's range, the bounds as doubles; the first and last reach to infinity), then x_lo, x_hi, y_lo, y_hi of a box
  /// holding the box, under either rule, of every bar whose x range meets the tile's
  /// (an empty box if none), then padding.
  AVec<double> cell_tile;
  static constexpr int kTileStride = 8;
  static constexpr double kMinCellWidth = 128.0; ///< a move is at most ~20 px
  static constexpr double kMaxCells = 65536.0;

  [[nodiscard]] bool empty() const { return bars.empty(); }
  [[nodiscard]] int size() const { return static_cast<int>(bars.size()); }
  /// The cell of x, floor((x - cell_x0) / cell_width) clamped to the grid (x *
  /// cell_scale is x / cell_width exactly, and rounding is monotonic: a bar reaching x
  /// is listed in cell_of(x)). Above 0 the floor is the truncation (no call to floor).
  [[nodiscard]] int cell_of(double x) const {
    const double c = (x - cell_x0) * cell_scale;
    if (!(c > 0.0)) return 0;
    return c >= cell_count - 1 ? cell_count - 1 : static_cast<int>(c);
  }
};

/// Builds the geometry of bars (ends[2k], ends[2k+1]) from the positions px, py.
FixedBars make_fixed_bars(const std::vector<int>& bar_a, const std::vector<int>& bar_b, const double* px,
                          const double* py, BarEngine engine);

/// A bar's memory of a mass lying on it: the side the mass came from.
struct BarContact {
  int bar = 0;
  int mass = 0;
  std::int8_t side = 0; ///< -1 left of a->b, +1 right, 0 started on the line
  bool operator==(const BarContact&) const = default;
};

/// A mass caught in a concave corner: the bar it went to and which end is the node.
struct BarCorner {
  int bar = -1;          ///< -1: not in a corner
  std::int8_t end = 0;   ///< 0: the node is the bar's start, 1: its end
  bool operator==(const BarCorner&) const = default;
};

/// How often the situations the inferred rules decide came up (diagnostics for
/// `bench races`, as Box2D keeps b2Counters): a remembered mass's move starting
/// farther than kSideTolerance from the bar's line on another side than the
/// remembered one (SideRule); a crossing point outside hit_margin but within
/// kTweakMargin of the bar's box; a concave joint past the next bar's far end
/// (far_end_corner).
struct BarCounters {
  long long far_starts = 0, near_end_misses = 0, far_end_corners = 0;
};

/// The dynamic part of the bar rules (belongs to a State).
struct BarMemory {
  std::vector<BarContact> contacts; ///< unordered; one entry per (bar, mass)
  std::vector<BarCorner> corners;   ///< [mass_count] once a mass met a bar, else empty
  BarCounters counters;             ///< diagnostics: not state, so not compared
  bool operator==(const BarMemory& o) const { return contacts == o.contacts && corners == o.corners; }

  /// The remembered side, or nullptr.
  [[nodiscard]] const BarContact* find(int bar, int mass) const;
  void remember(int bar, int mass, int side);
  void forget(int bar, int mass);
};

/// One mass's move this frame, as the container left it.
struct MassMove {
  double x0 = 0, y0 = 0;          ///< position before the move
  double free_x = 0, free_y = 0;  ///< end of the move before the container clamp
  double x = 0, y = 0;            ///< end after the clamp
  double vx = 0, vy = 0;          ///< velocity after gravity and friction (before the container's response)
};

/// Where a bar (or a corner) put the mass.
struct MassEnd {
  double x = 0, y = 0, vx = 0, vy = 0;
};

struct Surface {
  double friction = 1.0;   ///< Fs
  double reflection = 0.0; ///< Rs
  double width = 0.0, height = 0.0; ///< the container
};

/// The bar rules for mass `mass` after its move and the container clamp. Returns
/// true when bars decided the mass's position and velocity (`end`); false when the
/// mass moves as the container left it (position and velocity unchanged).
bool collide_with_fixed_bars(const FixedBars& bars, BarMemory& memory, int mass, const MassMove& move,
                             const Surface& surface, MassEnd& end);

/// Whether the move from (x0, y0) to (x, y) (as the container left it) may touch the
/// box of a bar, under either rule, by the tile `tile` (a row of cell_tile). When
/// false, collide_with_fixed_bars for a mass that no bar remembers and that is in no
/// corner changes nothing and returns false, so a stepper may leave it out: every bar
/// whose box the move touches has an x range that meets the move's, which lies in the
/// tile, so its box is in the tile's box. A move not inside the tile answers true.
[[nodiscard]] inline bool move_may_touch_tile(const double* tile, double x0, double y0, double x, double y) {
  const double lo = std::min(x0, x), hi = std::max(x0, x);
  if (!(lo >= tile[0] && hi <= tile[1])) return true;
  return hi >= tile[2] && lo <= tile[3] && std::max(y0, y) >= tile[4] && std::min(y0, y) <= tile[5];
}

/// The tile of the cell of x.
[[nodiscard]] inline const double* tile_of(const FixedBars& bars, double x) {
  return bars.cell_tile.data() + FixedBars::kTileStride * static_cast<std::size_t>(bars.cell_of(x));
}

/// move_may_touch_tile with the tile of the move's start.
[[nodiscard]] inline bool move_may_touch_bars(const FixedBars& bars, double x0, double y0, double x, double y) {
  return move_may_touch_tile(tile_of(bars, x0), x0, y0, x, y);
}

/// Where the original's writer puts mass `mass` at (x, y): 1e-4 (FixedBar.TWEAK) off
/// each bar that remembers it, toward the remembered side (docs/physics.md, "Fixed bars").
void tweak_for_writing(const FixedBars& bars, const BarMemory& memory, int mass, double& x, double& y);

/// java.awt.geom.Line2D.relativeCCW semantics: -1, 0 or +1 (docs/physics.md, "Fixed bars").
int relative_ccw(double x1, double y1, double x2, double y2, double px, double py);

} // namespace soda
