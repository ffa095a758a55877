// ModelDef: the editable, plain description of a SodaConstructor model.
//
// This is what the XML readers produce, what the writer consumes and what the
// genetic algorithm edits: plain structs in file order, ids kept for messages and
// writing, no derived data. `build_model` (model.hpp) validates a ModelDef and turns
// it into the static Model plus the initial State used by the engine, in the spirit
// of Box2D's body/joint definitions.
//
// Units: pixels and frames, y up, floor at y = 0; phases in cycles.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "constants.hpp"

namespace soda {

/// Gravity direction d in `vy -= g*d` (docs/physics.md, part 2): down = +1, up = -1, off = 0.
enum class GravityDirection : int { Up = -1, Off = 0, Down = 1 };

/// Wave mode: the sign of the phase advance (docs/physics.md, "The wave"). Manual does not
/// advance.
enum class WaveDirection : int { Reverse = -1, Manual = 0, Forward = 1 };

enum class LinkKind : std::uint8_t { Spring, Muscle, FixedBar };

/// A point of the model: a free mass (moves) or a fixed node (never moves).
struct NodeDef {
  std::string id;
  bool fixed = false;
  double x = 0.0;
  double y = 0.0;
  double vx = 0.0; ///< masses only; fixed nodes keep 0
  double vy = 0.0;

  bool operator==(const NodeDef&) const = default;
};

/// A link between nodes[a] and nodes[b] (indices into ModelDef::nodes).
struct LinkDef {
  LinkKind kind = LinkKind::Spring;
  int a = 0;
  int b = 0;
  double rest_length = 0.0; ///< springs and muscles
  double amplitude = 0.0;   ///< muscles: in [0, 1]
  double phase = 0.0;       ///< muscles: cycles, in [0, 1)

  bool operator==(const LinkDef&) const = default;
};

struct EnvironmentDef {
  double gravity = kDefaultGravity;
  double friction = kDefaultFriction;
  double springyness = kDefaultSpringyness; // (sic) spring constant k

  bool operator==(const EnvironmentDef&) const = default;
};

struct CollisionsDef {
  double surface_friction = kDefaultSurfaceFriction;     ///< tangential velocity kept
  double surface_reflection = kDefaultSurfaceReflection; ///< normal velocity factor

  bool operator==(const CollisionsDef&) const = default;
};

struct WaveDef {
  double amplitude = kDefaultWaveAmplitude; ///< in [0, 1]
  double phase = kDefaultWavePhase;         ///< cycles, in [0, 1)
  double speed = kDefaultWaveSpeed;         ///< cycles per frame, any sign

  bool operator==(const WaveDef&) const = default;
};

struct SettingsDef {
  GravityDirection gravity_direction = GravityDirection::Down;
  WaveDirection wave_direction = WaveDirection::Forward;
  bool autoreverse = true;

  bool operator==(const SettingsDef&) const = default;
};

struct ModelDef {
  std::string comment;
  std::string name; ///< later 1.x files and v2 files; not written by the 2003 writer
  int width = kDefaultWidth;
  int height = kDefaultHeight;
  EnvironmentDef environment;
  CollisionsDef collisions;
  WaveDef wave;
  SettingsDef settings;
  std::vector<NodeDef> nodes; ///< masses and fixed nodes, in file order
  std::vector<LinkDef> links; ///< in file order (it matters to the last bit)

  bool operator==(const ModelDef&) const = default;
};


/// Wraps a phase in cycles into [0, 1) as the original parser does (1.0 -> 0.0,
/// -0.25 -> 0.75). Exact for every finite input: x - floor(x) is exact except for
/// tiny negative x, where the rounded result can be 1.0 and is mapped to 0.
/// Inline, with floor found by comparisons on [-1, 2) (the wave moves by less than
/// a cycle per frame, so nearly every call lands there): std::floor is a library
/// call on baseline x86-64, and this runs once per creature per frame. Outside
/// that range, and for +-0 (whose sign floor keeps), std::floor; same bits either way.
inline double wrap_phase(double cycles) {
  double whole;
  if (cycles > 0.0 && cycles < 1.0) {
    whole = 0.0;
  } else if (cycles >= 1.0 && cycles < 2.0) {
    whole = 1.0;
  } else if (cycles >= -1.0 && cycles < 0.0) {
    whole = -1.0;
  } else {
    whole = std::floor(cycles);
  }
  const double wrapped = cycles - whole;
  return wrapped >= 1.0 ? 0.0 : wrapped;
}

/// The canonical form the original writer produces (docs/file-formats.md): fixed nodes first,
/// then masses (order kept inside each group), ids regenerated from one running
/// index (n0, n1, ..., m<k>, m<k+1>, ...), links grouped as springs, then muscles,
/// then fixed bars (order kept inside each group), endpoint indices remapped.
/// Idempotent. Mass order is unchanged, so traces keep their column order; link
/// regrouping can change trajectories in the last bits (docs/physics.md).
ModelDef canonical_form(const ModelDef& def);

} // namespace soda
