// Scene analysis: what a scene needs from the step, worked out once per model.
//
// The fast stepper (fast_step.hpp) is specialised for the features a scene has
// instead of branching on them per link and per frame. This file decides which
// features those are. Every "not needed" here is exact: skipping the work cannot
// change a single bit of the result compared with the reference step (step.hpp).
//
//  - muscles whose power (Aw*Am) is 0 are springs: their target is rest*(1 + (+-0))
//    = rest whatever the sine; no muscle left -> no wave work at all;
//  - muscles with the same phase share one sin per frame (real files quantise
//    phases to k/255, so there are few distinct ones);
//  - gravity whose product g*d is +0 is an identity (vy - (+0) = vy for every vy,
//    -0 included); g = 0 with gravity "up" gives -0 and is *not* skipped;
//  - no fixed bars -> no bar tests; bars whose ends are fixed nodes are fixed
//    segments, bars with a free-mass end moving ends in name only: the engine
//    takes every bar's geometry once (docs/physics.md, "Fixed bars"), so both step alike;
//  - a wall (floor, ceiling, left, right) that no mass can reach within the
//    frames asked for is not tested: after the friction step a mass moves at most
//    20 px/frame (the syrup speed limit, docs/physics.md, part 2), so kMaxMovePerFrame bounds it;
//  - links between two fixed nodes have no effect and are dropped.
#pragma once

#include <string>

#include "model.hpp"

namespace soda {

/// Upper bound on how far a free mass can move in one frame (px). The syrup limit
/// caps the speed after friction at kSyrupThreshold = 20 px/frame (up to rounding);
/// a fixed-bar response only shortens a move. The 5 % margin covers rounding of
/// the position update for any coordinate below kWallAnalysisMaxCoordinate.
inline constexpr double kMaxMovePerFrame = kSyrupThreshold * 1.05;

/// Beyond this coordinate magnitude the rounding of x + vx could exceed the
/// margin above, so every wall is tested.
inline constexpr double kWallAnalysisMaxCoordinate = 1e12;

/// Which container walls a step must test.
struct WallNeeds {
  bool floor = true;   ///< y < 0
  bool ceiling = true; ///< y > height
  bool sides = true;   ///< x < 0 or x > width (left and right together)
  bool operator==(const WallNeeds&) const = default;
};

/// For each wall, the number of frames for which no free mass can reach it from the
/// positions x[i*stride], y[i*stride] (i a free mass of `model`); 0 means it may be
/// hit in the next frame. Conservative: NaN or huge coordinates give 0 for every
/// wall. Capped at kSafeFramesCap.
inline constexpr long long kSafeFramesCap = 1LL << 40;
struct WallSafeFrames {
  long long floor = 0;
  long long ceiling = 0;
  long long sides = 0;
};
WallSafeFrames wall_safe_frames(const Model& model, const double* x, const double* y, long stride = 1);

/// The walls some free mass could reach within `frames` frames from x, y.
WallNeeds walls_within(const Model& model, const double* x, const double* y, long long frames);

enum class BarKind { None, FixedSegments, MovingEnds };

struct SceneNeeds {
  long long frame_budget = 0;

  int masses = 0;
  int links = 0;           ///< springs and muscles in the file
  int active_links = 0;    ///< minus the links between two fixed nodes
  int muscles = 0;         ///< muscles in the file
  int wave_muscles = 0;    ///< muscles whose power Aw*Am is not 0 (need a sin)
  int distinct_phases = 0; ///< sines per frame (one per distinct muscle phase)

  bool wave = false;     ///< some muscle needs the wave (wave_muscles > 0)
  bool gravity = false;  ///< g*d is not +0
  BarKind bars = BarKind::None;
  bool autoreverse = false; ///< autoreverse on and the initial wave not manual
  WallNeeds walls;          ///< walls reachable within the frame budget from the initial state

  /// One line, e.g. "wave(8 muscles, 6 sines) gravity floor sides bars:none".
  [[nodiscard]] std::string describe() const;
};

/// Analyses `model` for a run of `frame_budget` frames from its initial state.
SceneNeeds analyse_scene(const Model& model, long long frame_budget);

} // namespace soda
