// A Sodarace race as plain definition structs (docs/physics.md, "The race file"),
// like ModelDef: a timeout,
// a terrain model (the racer keeps its fixed nodes and bars: FilterFixedBars), the
// race constraints (each header value of the lane from the CONTENDER or the RACER,
// i.e. the terrain), and contenders with the results the file recorded. Read by
// formats/race_file.hpp; the lane is built from them by race_lane.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model_def.hpp"

namespace soda {

/// Where one header value of the lane comes from (docs/physics.md, "The race file").
enum class RaceSource : unsigned char { Contender, Racer };

struct RaceConstraints {
  RaceSource gravity = RaceSource::Contender;
  RaceSource friction = RaceSource::Contender;
  RaceSource springyness = RaceSource::Contender;
  RaceSource surface_friction = RaceSource::Contender;
  RaceSource surface_reflection = RaceSource::Contender;
  RaceSource wave_amplitude = RaceSource::Contender;
  RaceSource wave_phase = RaceSource::Contender;
  RaceSource wave_speed = RaceSource::Contender;
  RaceSource gravity_direction = RaceSource::Contender;
  RaceSource wave_direction = RaceSource::Contender;
  RaceSource autoreverse = RaceSource::Contender;
  bool operator==(const RaceConstraints&) const = default;
};

struct RaceContenderDef {
  ModelDef model;
  std::optional<double> recorded_frames; ///< <result frames="..."/>, if present (-1: not raced)
  int line = 0;                          ///< where the <contender> starts, for messages
};

/// The racer's largest timeout: it throws after 50,000 updates, and a timeout T ends
/// the race at update T + 3.
inline constexpr int kMaxRaceTimeout = 50000 - 3;

struct RaceDef {
  std::string source;   ///< file name, for messages and outputs
  int timeout = 10000;  ///< frames
  ModelDef terrain;     ///< the terrain model as written (the lane keeps its fixed nodes and bars)
  RaceConstraints constraints;
  std::vector<RaceContenderDef> contenders;
};

} // namespace soda
