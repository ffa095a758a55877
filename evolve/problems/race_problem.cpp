#include "evolve/problems/race_problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <optional>
#include <utility>

#include "core/batch_step.hpp"
#include "core/divergence.hpp"
#include "core/fast_step.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/number_text.hpp"
#include "core/race_lane.hpp"
#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/race_progress.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "evolve/problems/wire_format.hpp"
#include "evolve/problems/world_wire.hpp"
#include "formats/race_file.hpp"

namespace sodaevo {

RaceTerrain read_race_terrain(const std::string& file) {
  RaceTerrain t;
  t.file = file;
  t.text = soda::read_race_file_text(file);
  t.race = soda::read_race_text(t.text, file);
  return t;
}

RaceProblem::RaceProblem(const RaceFitnessConfig& race, std::vector<RaceTerrain> terrains, const WorldConfig& world,
                         const LimitsConfig& limits, long long describe_every)
    : race_(race), terrains_(std::move(terrains)), world_(world), limits_(limits), describe_every_(describe_every) {
  if (terrains_.empty()) throw soda::InputError("race problem: expected at least one terrain, got none");
  if (describe_every_ < 0) throw soda::InputError("race problem: negative descriptor sample interval");
}

bool race_describes(Descriptor d) {
  return d == Descriptor::MassCount || d == Descriptor::MuscleShare || d == Descriptor::Width || d == Descriptor::Height;
}

namespace {

/// The run's terrains: /fitness/race/terrains, or the curriculum's first stage.
std::vector<RaceTerrain> read_terrains(const RaceFitnessConfig& race) {
  if (!race.curriculum.empty()) return {read_race_terrain(race.curriculum.front().terrain)};
  std::vector<RaceTerrain> out;
  for (const std::string& file : race.terrains) out.push_back(read_race_terrain(file));
  return out;
}

bool evolves(const WorldConfig& world, const char* name) {
  return std::find(world.evolve.begin(), world.evolve.end(), name) != world.evolve.end();
}

/// Runs raced together on each terrain (run_races_together), and what each gave.
struct Together {
  std::vector<std::size_t> runs;                        ///< run indices, ascending
  std::vector<std::vector<soda::State>> states;         ///< [terrain][k] final state of runs[k]
  std::vector<std::vector<soda::RaceOutcome>> outcomes; ///< [terrain][k]
};

/// Races together.runs (each with its lanes and lane models, one per terrain) on
/// every terrain in fused scenes. False if a race throws: each run then races alone,
/// where the error is reported for the one it concerns.
bool race_together(const std::vector<Rollout>& runs,
                   const std::vector<std::pair<const std::vector<soda::RaceLane>*, const std::vector<soda::Model>*>>& lanes,
                   const std::vector<int>& timeouts, Together& together) {
  try {
    for (std::size_t t = 0; t < timeouts.size(); ++t) {
      std::vector<soda::State> states;
      for (std::size_t k = 0; k < together.runs.size(); ++k) {
        states.push_back(soda::make_state((*lanes[k].second)[t]));
        states.back().jitter = runs[together.runs[k]].jitter;
      }
      std::vector<soda::LaneRace> races;
      for (std::size_t k = 0; k < together.runs.size(); ++k) {
        races.push_back({&(*lanes[k].first)[t], &(*lanes[k].second)[t], timeouts[t], &states[k]});
      }
      together.outcomes.push_back(soda::run_races_together(races));
      together.states.push_back(std::move(states));
    }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

} // namespace

RaceProblem::RaceProblem(const FitnessConfig& fitness, const WorldConfig& world, const LimitsConfig& limits,
                         long long describe_every)
    : RaceProblem(fitness.race, read_terrains(fitness.race), world, limits, describe_every) {}

int RaceProblem::timeout_of(std::size_t t) const {
  const int base = race_.timeout > 0 ? race_.timeout : terrains_[t].race.timeout;
  return adaptive_timeout_ > 0 ? std::min(base, adaptive_timeout_) : base;
}

RaceProblem RaceProblem::at_stage(int stage) const {
  if (stage < 0 || static_cast<std::size_t>(stage) >= std::max<std::size_t>(1, race_.curriculum.size())) {
    throw soda::InputError("race problem: no curriculum stage " + std::to_string(stage));
  }
  if (race_.curriculum.empty()) return *this;
  RaceProblem p = *this;
  p.terrains_ = {read_race_terrain(race_.curriculum[static_cast<std::size_t>(stage)].terrain)};
  return p;
}

RaceProblem RaceProblem::with_adaptive_timeout(int frames) const {
  if (frames < 0 || frames > soda::kMaxRaceTimeout) throw soda::InputError("race problem: bad adaptive timeout");
  RaceProblem p = *this;
  p.adaptive_timeout_ = frames;
  return p;
}

soda::ModelDef RaceProblem::prepare(const soda::ModelDef& creature) const {
  if (std::optional<std::string> invalid = check_creature(creature, limits_)) {
    throw soda::InputError("creature " + *invalid);
  }
  soda::ModelDef m = creature;
  // The world, except what the creature chooses for itself (the race constraints
  // are CONTENDER: the lane takes the contender's values).
  const auto world = [&](const char* name, double& field, double value) {
    if (!evolves(world_, name)) field = value;
  };
  world("gravity", m.environment.gravity, world_.gravity);
  world("friction", m.environment.friction, world_.friction);
  world("springyness", m.environment.springyness, world_.springyness);
  world("surface_friction", m.collisions.surface_friction, world_.surface_friction);
  world("surface_reflection", m.collisions.surface_reflection, world_.surface_reflection);
  m.settings.gravity_direction = world_.gravity_direction;
  m.settings.wave_direction = soda::WaveDirection::Forward;
  m.settings.autoreverse = false;

  // At racing size: the racer's scale (half the container height over the root of
  // the sum of Lmax^2) is then 1 to the last bits.
  apply_sodarace_scale(m);
  // Placed in a default-height container (the racer scales by half of it): the
  // leftmost mass 20 px from the left wall, the lowest 5 px above the floor.
  double min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY;
  for (const soda::NodeDef& n : m.nodes) {
    min_x = std::min(min_x, n.x);
    max_x = std::max(max_x, n.x);
    min_y = std::min(min_y, n.y);
  }
  m.height = soda::kDefaultHeight;
  m.width = static_cast<int>(std::max<double>(soda::kDefaultWidth, std::ceil(max_x - min_x + 40.0)));
  for (soda::NodeDef& n : m.nodes) {
    n.x += 20.0 - min_x;
    n.y += 5.0 - min_y;
  }
  return m;
}

std::vector<Evaluation> RaceProblem::rollouts(const std::vector<Rollout>& runs) const {
  std::vector<Evaluation> results(runs.size());
  // The lanes and their models of each distinct prepared model (replicas share them).
  struct Lanes {
    const soda::ModelDef* prepared = nullptr;
    std::vector<soda::RaceLane> lanes;
    std::vector<soda::Model> models;
    std::string error;
  };
  std::vector<Lanes> built;
  std::vector<std::size_t> lanes_of_run(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    auto it = std::find_if(built.begin(), built.end(), [&](const Lanes& l) { return l.prepared == runs[i].prepared; });
    if (it == built.end()) {
      Lanes l;
      l.prepared = runs[i].prepared;
      try {
        for (const RaceTerrain& t : terrains_) {
          l.lanes.push_back(soda::build_lane(t.race.terrain, t.race.constraints, *l.prepared, "creature"));
          l.models.push_back(soda::build_lane_model(l.lanes.back()));
        }
      } catch (const std::exception& ex) {
        l.error = ex.what();
      }
      built.push_back(std::move(l));
      it = built.end() - 1;
    }
    lanes_of_run[i] = static_cast<std::size_t>(it - built.begin());
  }
  // The runs whose lanes were built raced together on each terrain
  // (run_races_together: a creature's replicas in lockstep lanes, the others in
  // fused scenes; the same outcomes and final states as one by one), when no
  // descriptors are measured.
  Together together;
  if (describe_every_ == 0) {
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (built[lanes_of_run[i]].error.empty()) together.runs.push_back(i);
    }
    std::vector<std::pair<const std::vector<soda::RaceLane>*, const std::vector<soda::Model>*>> lanes;
    for (std::size_t i : together.runs) lanes.emplace_back(&built[lanes_of_run[i]].lanes, &built[lanes_of_run[i]].models);
    std::vector<int> timeouts;
    for (std::size_t t = 0; t < terrains_.size(); ++t) timeouts.push_back(timeout_of(t));
    if (!race_together(runs, lanes, timeouts, together)) together = Together{};
  }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto it = built.begin() + static_cast<std::ptrdiff_t>(lanes_of_run[i]);
    Evaluation& e = results[i];
    if (!it->error.empty()) {
      e.reason = it->error;
      continue;
    }
    double sum = 0.0, worst = 0.0;
    std::vector<TerrainRaceResult> raced;
    Behaviour described{};
    bool healthy = true;
    for (std::size_t t = 0; t < terrains_.size() && healthy; ++t) {
      const soda::Model& model = it->models[t];
      soda::State state = soda::make_state(model);
      state.jitter = runs[i].jitter;
      soda::RaceOutcome o;
      std::optional<DescriptorMeter> meter;
      if (describe_every_ > 0) meter.emplace(model);
      const auto with_others = std::lower_bound(together.runs.begin(), together.runs.end(), i);
      try {
        if (with_others != together.runs.end() && *with_others == i) { // raced with the others
          const std::size_t k = static_cast<std::size_t>(with_others - together.runs.begin());
          state = std::move(together.states[t][k]);
          o = together.outcomes[t][k];
        } else {
          o = soda::run_race_fast(it->lanes[t], model, timeout_of(t), state, describe_every_,
                                  [&](const soda::State& s) { meter->observe(s); });
        }
      } catch (const std::exception& ex) {
        e.status = EvaluationStatus::Diverged;
        e.reason = terrains_[t].file + ": " + ex.what();
        healthy = false;
        break;
      }
      // A non-finite state still has the racer's result (a contender scaled by +inf
      // is NaN from the first update: the timeout formula), as the original reports
      // it; only descriptors cannot be measured on one.
      if (const int m = soda::first_non_finite_mass(model, state); m >= 0 && meter) {
        e.status = EvaluationStatus::Diverged;
        e.reason = terrains_[t].file + ": no descriptors: non-finite state of mass " + std::to_string(m) +
                   " at update " + std::to_string(o.updates);
        healthy = false;
        break;
      }
      sum += o.result;
      worst = t == 0 ? o.result : std::max(worst, o.result);
      if (race_.score == RaceScore::Progress) {
        const double start = soda::least_x(model, soda::make_state(model));
        raced.push_back({o.result, o.finished, timeout_of(t), track_progress(it->lanes[t], start, o.furthest_min_x)});
      }
      if (meter) {
        const Behaviour b = meter->behaviour();
        for (std::size_t d = 0; d < kDescriptorCount; ++d) described[d] += b[d] / static_cast<double>(terrains_.size());
      }
    }
    if (!healthy) continue;
    if (describe_every_ > 0) e.descriptors = behaviour_values(described);
    const double frames = race_.combine == RaceCombine::Worst ? worst : sum / static_cast<double>(terrains_.size());
    e.status = EvaluationStatus::Ok;
    e.distance = frames;
    e.px_per_frame = 0.0;
    e.fitness = race_.score == RaceScore::Progress ? -progress_cost(raced) : -frames;
  }
  return results;
}

soda::ModelDef RaceProblem::export_form(const soda::ModelDef& creature, const std::string& id,
                                        const Evaluation& evaluation) const {
  soda::ModelDef prepared = prepare(creature);
  prepared.name = id;
  std::string on;
  for (const RaceTerrain& t : terrains_) on += (on.empty() ? "" : ", ") + std::filesystem::path(t.file).filename().string();
  prepared.comment = "sodaevo " + id + ": race fitness " + soda::format_double_plain(evaluation.fitness) + " (" +
                     soda::format_double_plain(evaluation.distance) + " frames, " +
                     (terrains_.size() > 1 ? race_combine_name(race_.combine) + " over " : std::string("on ")) + on +
                     "; the original racer, 2004 bar rule)";
  return prepared;
}

void RaceProblem::write(WireWriter& out) const {
  out.text(kind());
  out.u8(static_cast<std::uint8_t>(race_.combine));
  out.u8(static_cast<std::uint8_t>(race_.score));
  out.i32(race_.timeout);
  out.u64(terrains_.size());
  for (const RaceTerrain& t : terrains_) {
    out.text(t.file);
    out.text(t.text);
  }
  write_world_and_limits(out, world_, limits_);
  out.u64(static_cast<std::uint64_t>(describe_every_));
  out.i32(adaptive_timeout_);
}

RaceProblem RaceProblem::read_fields(WireReader& in) {
  RaceFitnessConfig race;
  const int combine = in.u8();
  if (combine > 1) throw WireError("race problem: bad combine value " + std::to_string(combine));
  race.combine = static_cast<RaceCombine>(combine);
  const int score = in.u8();
  if (score > 1) throw WireError("race problem: bad score value " + std::to_string(score));
  race.score = static_cast<RaceScore>(score);
  race.timeout = in.i32();
  if (race.timeout < 0 || race.timeout > soda::kMaxRaceTimeout) throw WireError("race problem: bad timeout");
  const std::uint64_t count = in.u64();
  constexpr std::uint64_t kMaxTerrains = 64;
  if (count == 0 || count > kMaxTerrains) throw WireError("race problem: bad terrain count");
  std::vector<RaceTerrain> terrains;
  for (std::uint64_t k = 0; k < count; ++k) {
    RaceTerrain t;
    t.file = in.text();
    t.text = in.text();
    try {
      t.race = soda::read_race_text(t.text, t.file);
    } catch (const std::exception& ex) {
      throw WireError(std::string("race problem: ") + ex.what());
    }
    race.terrains.push_back(t.file);
    terrains.push_back(std::move(t));
  }
  WorldConfig w;
  LimitsConfig l;
  read_world_and_limits(in, "race problem", w, l);
  const std::uint64_t describe_every = in.u64();
  constexpr std::uint64_t kMaxDescribeEvery = 1000000;
  if (describe_every > kMaxDescribeEvery) throw WireError("race problem: bad descriptor sample interval");
  const int adaptive = in.i32();
  if (adaptive < 0 || adaptive > soda::kMaxRaceTimeout) throw WireError("race problem: bad adaptive timeout");
  return RaceProblem(race, std::move(terrains), w, l, static_cast<long long>(describe_every))
      .with_adaptive_timeout(adaptive);
}

} // namespace sodaevo
