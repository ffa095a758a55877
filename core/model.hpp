// Model and State: the static description of a scene and its dynamic state.
//
// As in MuJoCo (mjModel / mjData), everything that does not change while a scene
// runs lives in Model, built once from a ModelDef by build_model(), which is the
// one place that validates a model; everything that changes each frame lives in
// State. Hot data are structures of arrays.
//
// Points: one index space for masses and fixed nodes. Indices [0, mass_count) are
// the free masses in file order (their order matters: it is the update order, and
// autoreverse depends on which mass hits a wall first); [mass_count, point_count)
// are the fixed nodes in file order. Links address points by this index.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "fixed_bars.hpp"
#include "model_def.hpp"
#include "sine_jitter.hpp"

namespace soda {

enum class SideWall : std::int8_t { None = 0, Left = -1, Right = 1 };

struct Model {
  // --- world (docs/file-formats.md, v1) ---
  double width = kDefaultWidth;   ///< container: 0 <= x <= width
  double height = kDefaultHeight; ///< container: 0 <= y <= height
  double springyness = kDefaultSpringyness;
  double friction = kDefaultFriction;
  double gravity = kDefaultGravity;
  GravityDirection gravity_direction = GravityDirection::Down;
  double surface_friction = kDefaultSurfaceFriction;
  double surface_reflection = kDefaultSurfaceReflection;
  bool autoreverse = true;
  double wave_amplitude = kDefaultWaveAmplitude;
  double wave_speed = kDefaultWaveSpeed;

  // --- points ---
  int mass_count = 0;
  int point_count = 0;
  std::vector<int> node_of_point; ///< [point_count] index into ModelDef::nodes
  std::vector<int> point_of_node; ///< [nodes] inverse of node_of_point

  // --- force links (springs and muscles), file order; fixed bars excluded ---
  std::vector<int> link_a;                ///< [link_count] point index
  std::vector<int> link_b;                ///< [link_count] point index
  std::vector<double> link_rest;          ///< [link_count] rest length
  std::vector<std::uint8_t> link_muscle;  ///< [link_count] 1 for a muscle
  std::vector<double> link_amplitude;     ///< [link_count] muscle amplitude Am (0 for springs)
  std::vector<double> link_phase;         ///< [link_count] muscle phase (cycles)

  // --- derived constants (set_constants, as MuJoCo's mj_setConst): each formed
  // once per model by the rule's own expression (physics_rules.hpp), so that every
  // stepper reads the same bits ---
  double gravity_step = 0.0;      ///< g*d (rules::gravity_step)
  double air_keep = 1.0;          ///< 1 - f (rules::air_keep)
  std::vector<double> link_power; ///< [link_count] muscle power Aw*Am (rules::muscle_power); 0 for springs

  // --- fixed bars (collision segments), file order ---
  std::vector<int> bar_a; ///< [bar_count] point index
  std::vector<int> bar_b; ///< [bar_count] point index
  FixedBars fixed_bars;   ///< their geometry as the engine takes it (from x0, y0), chains, rule

  // --- initial state (as loaded) ---
  std::vector<double> x0, y0, vx0, vy0; ///< [point_count]
  double wave_phase0 = kDefaultWavePhase;
  WaveDirection wave_direction0 = WaveDirection::Forward;

  [[nodiscard]] int link_count() const { return static_cast<int>(link_a.size()); }
  [[nodiscard]] int bar_count() const { return static_cast<int>(bar_a.size()); }
  [[nodiscard]] bool is_mass(int point) const { return point < mass_count; }
};

struct State {
  std::vector<double> x, y;   ///< [point_count] positions (fixed nodes never change)
  std::vector<double> vx, vy; ///< [point_count] velocities (0 for fixed nodes)
  double wave_phase = 0.0;    ///< cycles, in [0, 1] (a running wave keeps 1.0: rules::wrap_moved_wave_phase)
  WaveDirection wave_mode = WaveDirection::Forward;
  SideWall last_side_wall = SideWall::None; ///< autoreverse memory (docs/physics.md, part 2)
  long long frame = 0;        ///< frames stepped since the state was made
  SineJitter jitter;          ///< this replica's sine jitter (sine_jitter.hpp); seed 0: exact
  BarMemory bar_memory;       ///< fixed bars: masses each bar remembers, corners (physics.md)
};

/// Validates `def` and builds the static model. Throws InputError naming the node
/// or link and the field for: no nodes, non-finite numbers, values outside the
/// original's ranges (constants.hpp), unnormalised amplitudes or phases, bad link
/// indices, a link from a node to itself, counts above the limits.
/// `bar_engine`: which original's fixed-bar box test the model steps with
/// (fixed_bars.hpp; SodaConstructor files are the 2003 engine's, a race lane the 2004 racer's).
Model build_model(const ModelDef& def, BarEngine bar_engine = BarEngine::SodaConstructor2003);

/// Forms the derived constants of `model` from its fields. build_model calls it; call
/// it again after changing gravity, friction, the wave amplitude or a link's muscle
/// flag or amplitude of a built Model by hand (the steppers assert, in builds with
/// assertions, that the constants are current).
void set_constants(Model& model);

/// Whether the derived constants are those set_constants forms, bit for bit.
[[nodiscard]] bool constants_current(const Model& model);

/// A link that moves with the wave: a muscle of power (Aw*Am) other than 0.
[[nodiscard]] inline bool is_wave_muscle(const Model& model, int link) { return model.link_power[link] != 0.0; }

/// The state as loaded (frame 0).
State make_state(const Model& model);

/// The steppers index a state's arrays by the model's points without bounds
/// checks (the frame loops cannot afford them), so each run() checks its states
/// once before its frames. This throws std::invalid_argument, naming `who`, unless
/// `state` has `points` entries in each of x, y, vx and vy (a state of a model of
/// that many points, as make_state gives).
void require_state_size(const State& state, int points, const char* who);

/// The same for a batch of `count` states: none null, none given twice (one State
/// for two creatures would be stepped twice per frame and end with one of their
/// results), states[c] of points_of(c) points. Messages name the state's index.
void require_batch_states(State* const* states, int count, const std::function<int(int)>& points_of,
                          const char* who);

/// `def` with the positions, velocities and wave of `state` (for writing the final
/// state). `model` must have been built from `def`.
ModelDef def_with_state(const ModelDef& def, const Model& model, const State& state);

/// Mean x and y over the free masses (0 if there are none), summed in mass order.
struct Point2 {
  double x = 0.0;
  double y = 0.0;
};
Point2 mass_centroid(const Model& model, const State& state);

} // namespace soda
