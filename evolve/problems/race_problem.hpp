// RaceProblem: how fast a creature races over Sodarace terrains, as the original
// racer (2004) races a contender (core/race_lane.hpp; /fitness/kind "race").
//
// A creature is checked against the limits and prepared as a contender the
// original racer accepts: the world applied (except what the creature evolves),
// wave forward, autoreverse off, scaled as the racer scales contenders (so the
// file holds the creature at the size it races, and the racer's own scale is 1
// to the last bits), in a container of the default height 422 (the racer scales by
// half the contender's own container height). The prepared model is exactly what
// `export` writes, so `sodaevo race TERRAIN.xml EXPORTED.xml` and the original
// racer give the result the run logged. A rollout races it on every terrain, each
// in its own lane, until the finish or the timeout (the race file's, or
// /fitness/race/timeout): its result is the racer's, frames to the finish or
// timeout + the fraction of the way left. Several terrains score their mean or the
// worst. Fewer frames is better, so fitness = -frames; Evaluation::distance holds
// the frames (the score in its natural unit), px_per_frame is 0. With
// /fitness/race/score "progress" the fitness is instead minus the progress cost of
// evolve/problems/race_progress.hpp (files finished first, then frames and the furthest
// ground held); the frames logged stay the racer's.
//
// With a descriptor sample interval (MAP-Elites), the same race also measures the
// descriptors of evolve/problems/descriptors.hpp that mean the same in a lane as on the
// floor (race_descriptor_names: mass count, muscle share, width, height; the
// floor-relative ones do not, the terrain is the ground), every k frames of the
// race and after its last, the mean over the terrains. The race is then stepped
// in chunks of k frames with the finish watched after every frame: the same
// bits as one run (tests/test_race_fitness.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/race_def.hpp"
#include "core/race_lane.hpp"
#include "evolve/problems/descriptors.hpp"
#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/fitness_settings.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/problems/world_settings.hpp"

namespace sodaevo {

/// One terrain of a race problem: the race file's text (it travels to MPI
/// workers as is) and what it reads to.
struct RaceTerrain {
  std::string file; ///< as configured (for messages and comments)
  std::string text;
  soda::RaceDef race;
};

/// Reads a race file into a RaceTerrain. Throws soda::InputError.
RaceTerrain read_race_terrain(const std::string& file);

class RaceProblem final : public Problem {
 public:
  /// `describe_every` > 0: measure the descriptors every that many frames of a race.
  RaceProblem(const RaceFitnessConfig& race, std::vector<RaceTerrain> terrains, const WorldConfig& world,
              const LimitsConfig& limits, long long describe_every = 0);
  /// The run's problem: /fitness/race (its terrains read now), /world and /limits,
  /// measuring descriptors every `describe_every` frames (0: none).
  RaceProblem(const FitnessConfig& fitness, const WorldConfig& world, const LimitsConfig& limits,
              long long describe_every);

  [[nodiscard]] const std::vector<RaceTerrain>& terrains() const { return terrains_; }

  [[nodiscard]] FitnessKind fitness_kind() const override { return FitnessKind::Race; }
  [[nodiscard]] soda::ModelDef prepare(const soda::ModelDef& creature) const override;
  /// Each run on every terrain; the lanes of one prepared model are built once and
  /// shared by its replicas; all race together (run_races_together: the results of
  /// run_race_fast one by one), or one by one when descriptors are measured. A
  /// lane that cannot be built is Invalid; a non-finite state at the end of a race
  /// is Diverged.
  [[nodiscard]] std::vector<Evaluation> rollouts(const std::vector<Rollout>& runs) const override;
  [[nodiscard]] soda::ModelDef export_form(const soda::ModelDef& creature, const std::string& id,
                                           const Evaluation& evaluation) const override;
  void write(WireWriter& out) const override;
  /// The fields `write` wrote after the kind tag.
  static RaceProblem read_fields(WireReader& in);

  /// The timeout raced on terrain `t`: /fitness/race/timeout, or the race file's;
  /// the adaptive timeout when it is shorter.
  [[nodiscard]] int timeout_of(std::size_t t) const;
  /// This problem on stage `stage` of /fitness/race/curriculum (its terrain; stage
  /// 0 is the run's). Throws soda::InputError for a stage the curriculum lacks.
  [[nodiscard]] RaceProblem at_stage(int stage) const;
  /// This problem racing with an adaptive timeout of `frames` (0: none;
  /// evolve/runs/race_schedule.hpp).
  [[nodiscard]] RaceProblem with_adaptive_timeout(int frames) const;

 private:
  RaceFitnessConfig race_;
  std::vector<RaceTerrain> terrains_;
  WorldConfig world_;
  LimitsConfig limits_;
  long long describe_every_ = 0;
  int adaptive_timeout_ = 0;
};

/// The descriptors a race measures (descriptor_names order): mass_count,
/// muscle_share, width, height.
bool race_describes(Descriptor d);

} // namespace sodaevo
