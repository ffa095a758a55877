// Sodarace race files (`<!DOCTYPE sodarace>`, spec 3.1): a timeout, a terrain model
// read through the racer's FilterFixedBars, the race constraints (each header value
// from the CONTENDER or the RACER, i.e. the terrain), and contenders with the results
// the file recorded. Plain definition structs, as ModelDef; the lane is built from
// them by race_lane.hpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model_def.hpp"

namespace soda {

/// Where one header value of the lane comes from (spec 3.1).
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

/// Reads race XML held in memory; `source_name` names it in messages. Throws
/// InputError naming file, line, column, element and attribute, expected and got, for:
/// another root, an unknown racer class or filter, no terrain (or no fixed node in
/// it), a terrain wider than the lane's container can be, a timeout that is not an
/// integer in [1, kMaxRaceTimeout], a constraint other than CONTENDER or RACER.
RaceDef read_race_text(std::string_view text, const std::string& source_name);
RaceDef read_race_file(const std::filesystem::path& path);

/// Whether the XML text's root element is <race> (cheap look at the text).
bool looks_like_race(std::string_view text);

} // namespace soda
