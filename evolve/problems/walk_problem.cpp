#include "walk_problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <iterator>

#include "core/batch_step.hpp"
#include "core/divergence.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "core/number_text.hpp"
#include "core/stability.hpp"
#include "core/step_failure.hpp"
#include "core/stepping.hpp"
#include "evolve/problems/creature_limits.hpp"
#include "evolve/problems/descriptors.hpp"
#include "evolve/problems/honesty.hpp"
#include "evolve/problems/wire_format.hpp"
#include "evolve/problems/world_wire.hpp"

namespace sodaevo {

std::optional<double> sodarace_scale(const soda::ModelDef& c) {
  double sum = 0.0;
  bool any = false;
  for (const soda::LinkDef& l : c.links) {
    if (l.kind == soda::LinkKind::FixedBar) continue;
    double lmax = l.rest_length;
    if (l.kind == soda::LinkKind::Muscle) lmax = l.rest_length * (1.0 + l.amplitude * c.wave.amplitude);
    sum += lmax * lmax;
    any = true;
  }
  if (!any || !(sum > 0.0) || !std::isfinite(sum)) return std::nullopt;
  return 211.0 / std::sqrt(sum);
}

void apply_sodarace_scale(soda::ModelDef& m) {
  const std::optional<double> s = sodarace_scale(m);
  if (!s) throw soda::InputError("cannot scale: the creature has no springs or muscles of non-zero length");
  for (soda::NodeDef& n : m.nodes) {
    n.x *= *s;
    n.y *= *s;
    n.vx *= *s;
    n.vy *= *s;
  }
  for (soda::LinkDef& l : m.links) l.rest_length *= *s;
  m.environment.gravity *= *s;
  if (!soda::kGravityRange.contains(m.environment.gravity)) {
    throw soda::InputError("Sodarace scaling by " + std::to_string(*s) + " gives gravity " +
                           std::to_string(m.environment.gravity) + ", above the original's limit 4 (creature too small)");
  }
}

WalkProblem::WalkProblem(const FitnessConfig& fitness, const WorldConfig& world, const LimitsConfig& limits,
                         long long describe_every)
    : fitness_(fitness), world_(world), limits_(limits), describe_every_(describe_every) {
  if (describe_every_ < 0) throw std::invalid_argument("WalkProblem: negative descriptor sample interval");
}

namespace {

bool world_evolves(const WorldConfig& world, const char* name) {
  return std::find(world.evolve.begin(), world.evolve.end(), name) != world.evolve.end();
}

} // namespace

soda::ModelDef WalkProblem::prepare(const soda::ModelDef& creature) const {
  if (std::optional<std::string> invalid = check_creature(creature, limits_)) {
    throw soda::InputError("creature " + *invalid);
  }
  soda::ModelDef m = creature;
  if (!world_evolves(world_, "gravity")) m.environment.gravity = world_.gravity;
  if (!world_evolves(world_, "friction")) m.environment.friction = world_.friction;
  if (!world_evolves(world_, "springyness")) m.environment.springyness = world_.springyness;
  if (!world_evolves(world_, "surface_friction")) m.collisions.surface_friction = world_.surface_friction;
  if (!world_evolves(world_, "surface_reflection")) m.collisions.surface_reflection = world_.surface_reflection;
  m.settings.gravity_direction = world_.gravity_direction;
  m.settings.wave_direction = soda::WaveDirection::Forward;
  m.settings.autoreverse = false;

  if (fitness_.scaling == FitnessScaling::Sodarace) apply_sodarace_scale(m);

  // Place the creature: leftmost mass at the middle of a container wide enough
  // that no mass can reach a side wall (speed is at most 20 px/frame), lowest mass
  // drop_height above the floor, and a ceiling out of reach too.
  double min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY, max_y = -INFINITY;
  for (const soda::NodeDef& n : m.nodes) {
    min_x = std::min(min_x, n.x);
    max_x = std::max(max_x, n.x);
    min_y = std::min(min_y, n.y);
    max_y = std::max(max_y, n.y);
  }
  const double reach = soda::kSyrupThreshold * static_cast<double>(fitness_.frames + fitness_.settle_frames + 1);
  const double extent_x = max_x - min_x, extent_y = max_y - min_y;
  const double width = std::ceil(2.0 * (reach + extent_x) + 100.0);
  const double height = std::ceil(reach + extent_y + fitness_.drop_height + 100.0);
  if (!(width <= soda::kMaxContainerSide && height <= soda::kMaxContainerSide)) {
    throw soda::InputError("the evaluation needs a container wider than the format allows (too many frames)");
  }
  m.width = static_cast<int>(width);
  m.height = static_cast<int>(height);
  const double dx = std::floor(width / 2.0 - extent_x / 2.0) - min_x;
  const double dy = fitness_.drop_height - min_y;
  for (soda::NodeDef& n : m.nodes) {
    n.x += dx;
    n.y += dy;
  }
  if (fitness_.stability_margin_min > 0.0) {
    const soda::Model model = soda::build_model(m);
    const soda::StabilityPrediction p = soda::predict_stability(model, soda::make_state(model), fitness_.stepping());
    if (p.margin < fitness_.stability_margin_min) {
      throw soda::InputError("stability margin " + soda::format_double_plain(p.margin) + " of " +
                             soda::stepping_label(fitness_.stepping()) + " (omega_max^2 " +
                             soda::format_double_plain(p.omega_max * p.omega_max) +
                             ") below /fitness/stability_margin_min " +
                             soda::format_double_plain(fitness_.stability_margin_min));
    }
  }
  return m;
}

soda::ModelDef WalkProblem::export_form(const soda::ModelDef& creature, const std::string& id,
                                        const Evaluation& evaluation) const {
  soda::ModelDef prepared = prepare(creature);
  prepared.name = id;
  prepared.comment = "sodaevo " + id + ": fitness " + soda::format_double_plain(evaluation.fitness) +
                     " (centroid moved " + soda::format_double_plain(evaluation.distance) + " px in " +
                     std::to_string(fitness_.frames) + " frames after " + std::to_string(fitness_.settle_frames) +
                     " settle frames)";
  return prepared;
}

namespace {

/// The score of a healthy run whose centroid moved from `start` (after settling)
/// to `end`.
Evaluation score_distance(soda::Point2 start, soda::Point2 end, const FitnessConfig& fitness) {
  Evaluation e;
  e.distance = end.x - start.x;
  e.px_per_frame = e.distance / static_cast<double>(fitness.frames);
  switch (fitness.direction) {
    case WalkDirection::Right: e.fitness = e.distance; break;
    case WalkDirection::Left: e.fitness = -e.distance; break;
    case WalkDirection::Either: e.fitness = std::fabs(e.distance); break;
  }
  e.status = EvaluationStatus::Ok;
  return e;
}

/// The score of a run of `model` whose centroid was `start` after settling and
/// whose state is now `state`.
Evaluation score_run(const soda::Model& model, const soda::State& state, soda::Point2 start,
                     const FitnessConfig& fitness) {
  const soda::Point2 end = soda::mass_centroid(model, state);
  if (const int i = soda::first_non_finite_mass(model, state); i >= 0) {
    Evaluation e;
    e.status = EvaluationStatus::Diverged;
    e.reason = "non-finite state of mass " + std::to_string(i) + " at frame " + std::to_string(state.frame);
    return e;
  }
  return score_distance(start, end, fitness);
}

/// Frames between two non-finite checks when only those are asked for: the check
/// costs a pass over the masses, the step a pass over the links.
constexpr long long kFiniteCheckInterval = 64;

/// Whether the fitness asks for more than the batched soda run gives: another
/// stepping, the energy check, or the honesty re-run.
bool needs_watched_run(const FitnessConfig& fitness) {
  return fitness.mode != soda::PhysicsMode::Soda || fitness.divergence != DivergenceCheck::Finite ||
         fitness.honesty_max_change > 0.0;
}

} // namespace

std::vector<Evaluation> WalkProblem::rollouts(const std::vector<Rollout>& runs) const {
  std::vector<Evaluation> results(runs.size());
  if (needs_watched_run(fitness_)) {
    for (std::size_t i = 0; i < runs.size(); ++i) results[i] = watched_rollout(runs[i]);
    return results;
  }
  // One Model per distinct prepared model: the replicas of a creature share it
  // (and so their topology: the batch stepper runs them in lockstep lanes).
  std::vector<soda::Model> models;
  models.reserve(runs.size());
  std::vector<const soda::ModelDef*> built_from;
  std::vector<std::size_t> model_of(runs.size(), SIZE_MAX); // runs[i] -> models[k]
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto same = std::find(built_from.begin(), built_from.end(), runs[i].prepared);
    if (same != built_from.end()) {
      model_of[i] = static_cast<std::size_t>(same - built_from.begin());
      continue;
    }
    try {
      models.push_back(soda::build_model(*runs[i].prepared));
      built_from.push_back(runs[i].prepared);
      model_of[i] = models.size() - 1;
    } catch (const std::exception& ex) {
      results[i].reason = ex.what();
    }
  }
  std::vector<std::size_t> index; // result index of states[k]
  std::vector<const soda::Model*> model_ptrs;
  std::vector<soda::State> states;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (model_of[i] == SIZE_MAX) continue; // its model could not be built
    index.push_back(i);
    model_ptrs.push_back(&models[model_of[i]]);
    states.push_back(soda::make_state(models[model_of[i]]));
    states.back().jitter = runs[i].jitter;
  }
  if (states.empty()) return results;
  // The states step together in the batch stepper, which equals the reference
  // step bit for bit for each, sine jitter included (tests/test_batch_step.cpp,
  // tests/test_sine_jitter.cpp), so fitness depends neither on which stepper runs
  // nor on which rollouts share a batch. Replicas of a creature are one Model
  // given several times: the batch stepper puts them in lockstep lanes.
  std::vector<soda::State*> pointers;
  for (soda::State& s : states) pointers.push_back(&s);
  const long long total = static_cast<long long>(fitness_.settle_frames) + fitness_.frames;
  std::vector<bool> jittered;
  for (const soda::State& s : states) jittered.push_back(s.jitter.seed != 0);
  soda::BatchStepper stepper(model_ptrs, total, {}, jittered); // planned once, for these states
  auto run_all = [&](long long frames) { stepper.run(pointers, frames); };
  run_all(fitness_.settle_frames);
  std::vector<soda::Point2> start;
  for (std::size_t k = 0; k < states.size(); ++k) start.push_back(soda::mass_centroid(*model_ptrs[k], states[k]));
  // Descriptors sampled between chunks of frames: chunks give the bits of one long
  // run (BatchStepper::run steps frame by frame), so the score is the same.
  std::vector<DescriptorMeter> meters;
  if (describe_every_ > 0) {
    for (const soda::Model* m : model_ptrs) meters.emplace_back(*m);
    for (long long done = 0; done < fitness_.frames;) {
      const long long n = std::min(describe_every_, fitness_.frames - done);
      run_all(n);
      done += n;
      for (std::size_t k = 0; k < states.size(); ++k) meters[k].observe(states[k]);
    }
  } else {
    run_all(fitness_.frames);
  }
  for (std::size_t k = 0; k < states.size(); ++k) {
    Evaluation& e = results[index[k]];
    e = score_run(*model_ptrs[k], states[k], start[k], fitness_);
    if (e.ok() && !meters.empty()) e.descriptors = behaviour_values(meters[k].behaviour());
  }
  return results;
}

Evaluation WalkProblem::rollout_with(const soda::ModelDef& prepared, const soda::Stepping& stepping,
                                     const soda::SineJitter& jitter) const {
  Evaluation e;
  soda::Model model;
  try {
    model = soda::build_model(prepared);
    soda::validate_stepping(stepping);
  } catch (const std::exception& ex) {
    e.reason = ex.what();
    return e;
  }
  // The fast stepper equals the reference step bit for bit (tests/test_fast_step.cpp),
  // so fitness does not depend on which one runs.
  soda::State state = soda::make_state(model);
  state.jitter = jitter;
  soda::FrameStepper stepper(model, stepping, fitness_.settle_frames + fitness_.frames);
  const bool energy = fitness_.divergence == DivergenceCheck::Energy;
  soda::DivergenceMonitor monitor(model, state, {}, energy);
  const long long total = fitness_.settle_frames + fitness_.frames;
  soda::Point2 start = soda::mass_centroid(model, state);
  std::optional<DescriptorMeter> meter;
  if (describe_every_ > 0) meter.emplace(model);
  long long next_sample = fitness_.settle_frames + describe_every_;
  for (long long done = 0; done < total;) {
    if (done == fitness_.settle_frames) start = soda::mass_centroid(model, state);
    long long n = energy ? 1 : kFiniteCheckInterval;
    if (done < fitness_.settle_frames) n = std::min(n, fitness_.settle_frames - done);
    else if (meter) n = std::min(n, next_sample - done);
    n = std::min(n, total - done);
    try {
      stepper.run(state, n);
    } catch (const soda::StepFailure& failure) { // an implicit integrator's Newton solve failed
      e.status = EvaluationStatus::Diverged;
      e.reason = failure.reason + " (by frame " + std::to_string(failure.frame) + ")";
      return e;
    }
    done += n;
    if (!monitor.check(state)) {
      e.status = EvaluationStatus::Diverged;
      e.reason = monitor.result().reason + " (by frame " + std::to_string(monitor.result().frame) + ")";
      return e;
    }
    if (meter && done > fitness_.settle_frames && (done == next_sample || done == total)) {
      meter->observe(state);
      next_sample += describe_every_;
    }
  }
  e = score_distance(start, soda::mass_centroid(model, state), fitness_);
  if (meter) e.descriptors = behaviour_values(meter->behaviour());
  return e;
}

Evaluation WalkProblem::watched_rollout(const Rollout& run) const {
  const soda::ModelDef& prepared = *run.prepared;
  Evaluation e = rollout_with(prepared, fitness_.stepping(), run.jitter);
  if (!e.ok() || !(fitness_.honesty_max_change > 0.0)) return e;
  const soda::Stepping refined = refined_stepping(fitness_.stepping(), fitness_.honesty_substeps_factor);
  const Evaluation r = rollout_with(prepared, refined, run.jitter);
  if (!r.ok()) {
    Evaluation flagged;
    flagged.status = EvaluationStatus::Diverged;
    flagged.reason = "dishonest: with " + soda::stepping_label(refined) + " it " + r.reason;
    return flagged;
  }
  e.honesty_change = relative_change(e.distance, r.distance);
  if (std::fabs(e.honesty_change) > fitness_.honesty_max_change) {
    Evaluation flagged;
    flagged.status = EvaluationStatus::Diverged;
    flagged.honesty_change = e.honesty_change;
    flagged.reason = "dishonest: distance " + soda::format_double_plain(e.distance) + " px becomes " +
                     soda::format_double_plain(r.distance) + " px with " + soda::stepping_label(refined) +
                     " (change " + soda::format_double_plain(e.honesty_change) + ", above /fitness/honesty/max_change)";
    return flagged;
  }
  return e;
}

void WalkProblem::write(WireWriter& out) const {
  out.text(kind());
  out.u64(static_cast<std::uint64_t>(fitness_.frames));
  out.u64(static_cast<std::uint64_t>(fitness_.settle_frames));
  out.u8(static_cast<std::uint8_t>(fitness_.direction));
  out.u8(static_cast<std::uint8_t>(fitness_.scaling));
  out.f64(fitness_.drop_height);
  out.u8(static_cast<std::uint8_t>(fitness_.mode));
  out.u8(static_cast<std::uint8_t>(fitness_.integrator));
  out.i32(fitness_.substeps);
  out.u8(static_cast<std::uint8_t>(fitness_.divergence));
  out.f64(fitness_.honesty_max_change);
  out.i32(fitness_.honesty_substeps_factor);
  out.f64(fitness_.stability_margin_min);
  write_world_and_limits(out, world_, limits_);
  out.u64(static_cast<std::uint64_t>(describe_every_));
}

namespace {

constexpr std::uint64_t kMaxDescribeEvery = 1000000000;

template <typename Enum>
Enum enum_field(int v, int lo, int hi, const char* what) {
  if (v < lo || v > hi) throw WireError(std::string("walk problem: bad ") + what + " value " + std::to_string(v));
  return static_cast<Enum>(v);
}

} // namespace

WalkProblem WalkProblem::read_fields(WireReader& in) {
  FitnessConfig f;
  f.frames = static_cast<long long>(in.u64());
  f.settle_frames = static_cast<long long>(in.u64());
  f.direction = enum_field<WalkDirection>(in.u8(), 0, 2, "direction");
  f.scaling = enum_field<FitnessScaling>(in.u8(), 0, 1, "scaling");
  f.drop_height = in.f64();
  f.mode = enum_field<soda::PhysicsMode>(in.u8(), 0, 1, "physics mode");
  f.integrator = enum_field<soda::Integrator>(in.u8(), 0, static_cast<int>(std::size(soda::kIntegrators)) - 1,
                                              "integrator");
  f.substeps = in.i32();
  f.divergence = enum_field<DivergenceCheck>(in.u8(), 0, 1, "divergence check");
  f.honesty_max_change = in.f64();
  f.honesty_substeps_factor = in.i32();
  f.stability_margin_min = in.f64();
  WorldConfig w;
  LimitsConfig l;
  read_world_and_limits(in, "walk problem", w, l);
  const std::uint64_t describe_every = in.u64();
  if (describe_every > kMaxDescribeEvery) throw WireError("walk problem: bad descriptor sample interval");
  return WalkProblem(f, w, l, static_cast<long long>(describe_every));
}

} // namespace sodaevo
