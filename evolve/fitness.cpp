#include "fitness.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <vector>

#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/number_text.hpp"
#include "core/batch_step.hpp"
#include "core/divergence.hpp"
#include "core/stepping.hpp"
#include "evolve/creature_graph.hpp"
#include "evolve/honesty.hpp"

namespace sodaevo {

std::optional<std::string> check_creature(const soda::ModelDef& c, const LimitsConfig& limits) {
  const int masses = static_cast<int>(c.nodes.size());
  if (masses < limits.min_masses) {
    return "has " + std::to_string(masses) + " masses, fewer than limits.min_masses " + std::to_string(limits.min_masses);
  }
  if (masses > limits.max_masses) {
    return "has " + std::to_string(masses) + " masses, more than limits.max_masses " + std::to_string(limits.max_masses);
  }
  if (static_cast<int>(c.links.size()) > limits.max_links) {
    return "has " + std::to_string(c.links.size()) + " links, more than limits.max_links " + std::to_string(limits.max_links);
  }
  if (c.links.empty()) return "has no links";
  for (const soda::NodeDef& n : c.nodes) {
    if (n.fixed) return "has a fixed node ('" + n.id + "'); creatures are free masses only";
  }
  for (const soda::LinkDef& l : c.links) {
    if (l.kind == soda::LinkKind::FixedBar) return "has a fixed bar; creatures have springs and muscles only";
    if (l.a < 0 || l.b < 0 || l.a >= masses || l.b >= masses || l.a == l.b) return "has a link with bad ends";
  }
  if (!is_connected(c)) return "is not connected (some masses are not linked to the rest)";
  return std::nullopt;
}

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

namespace {

bool evolves(const WorldConfig& world, const char* name) {
  return std::find(world.evolve.begin(), world.evolve.end(), name) != world.evolve.end();
}

} // namespace

soda::ModelDef prepare_for_evaluation(const soda::ModelDef& creature, const FitnessConfig& fitness,
                                      const WorldConfig& world) {
  soda::ModelDef m = creature;
  if (!evolves(world, "gravity")) m.environment.gravity = world.gravity;
  if (!evolves(world, "friction")) m.environment.friction = world.friction;
  if (!evolves(world, "springyness")) m.environment.springyness = world.springyness;
  if (!evolves(world, "surface_friction")) m.collisions.surface_friction = world.surface_friction;
  if (!evolves(world, "surface_reflection")) m.collisions.surface_reflection = world.surface_reflection;
  m.settings.gravity_direction = world.gravity_direction;
  m.settings.wave_direction = soda::WaveDirection::Forward;
  m.settings.autoreverse = false;

  if (fitness.scaling == FitnessScaling::Sodarace) {
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
  const double reach = soda::kSyrupThreshold * static_cast<double>(fitness.frames + fitness.settle_frames + 1);
  const double extent_x = max_x - min_x, extent_y = max_y - min_y;
  const double width = std::ceil(2.0 * (reach + extent_x) + 100.0);
  const double height = std::ceil(reach + extent_y + fitness.drop_height + 100.0);
  if (!(width <= soda::kMaxContainerSide && height <= soda::kMaxContainerSide)) {
    throw soda::InputError("the evaluation needs a container wider than the format allows (too many frames)");
  }
  m.width = static_cast<int>(width);
  m.height = static_cast<int>(height);
  const double dx = std::floor(width / 2.0 - extent_x / 2.0) - min_x;
  const double dy = fitness.drop_height - min_y;
  for (soda::NodeDef& n : m.nodes) {
    n.x += dx;
    n.y += dy;
  }
  return m;
}

soda::ModelDef export_form(const soda::ModelDef& creature, const std::string& id, const Evaluation& evaluation,
                           const RunConfig& config) {
  soda::ModelDef prepared = prepare_for_evaluation(creature, config.fitness, config.world);
  prepared.name = id;
  prepared.comment = "sodaevo " + id + ": fitness " + soda::format_double_plain(evaluation.fitness) +
                     " (centroid moved " + soda::format_double_plain(evaluation.distance) + " px in " +
                     std::to_string(config.fitness.frames) + " frames after " +
                     std::to_string(config.fitness.settle_frames) + " settle frames)";
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
  for (int i = 0; i < model.mass_count; ++i) {
    if (!std::isfinite(state.x[i]) || !std::isfinite(state.y[i]) || !std::isfinite(state.vx[i]) ||
        !std::isfinite(state.vy[i])) {
      Evaluation e;
      e.status = EvaluationStatus::Diverged;
      e.reason = "non-finite state of mass " + std::to_string(i) + " at frame " + std::to_string(state.frame);
      return e;
    }
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

Evaluation evaluate_watched(const soda::ModelDef& prepared, const FitnessConfig& fitness);

} // namespace

std::vector<Evaluation> evaluate_prepared_batch(const std::vector<const soda::ModelDef*>& prepared,
                                                const FitnessConfig& fitness) {
  std::vector<Evaluation> results(prepared.size());
  if (needs_watched_run(fitness)) {
    for (std::size_t i = 0; i < prepared.size(); ++i) results[i] = evaluate_watched(*prepared[i], fitness);
    return results;
  }
  std::vector<soda::Model> models;
  models.reserve(prepared.size());
  std::vector<std::size_t> index; // result index of models[k]
  for (std::size_t i = 0; i < prepared.size(); ++i) {
    try {
      models.push_back(soda::build_model(*prepared[i]));
      index.push_back(i);
    } catch (const std::exception& ex) {
      results[i].reason = ex.what();
    }
  }
  if (models.empty()) return results;
  // The batch stepper equals the reference step bit for bit for each model
  // (tests/test_batch_step.cpp), so fitness depends neither on which stepper runs
  // nor on which creatures share a batch.
  std::vector<const soda::Model*> model_ptrs;
  std::vector<soda::State> states;
  for (const soda::Model& m : models) {
    model_ptrs.push_back(&m);
    states.push_back(soda::make_state(m));
  }
  std::vector<soda::State*> state_ptrs;
  for (soda::State& s : states) state_ptrs.push_back(&s);
  soda::BatchStepper stepper(model_ptrs, static_cast<long long>(fitness.settle_frames) + fitness.frames);
  stepper.run(state_ptrs, fitness.settle_frames);
  std::vector<soda::Point2> start;
  for (std::size_t k = 0; k < models.size(); ++k) start.push_back(soda::mass_centroid(models[k], states[k]));
  stepper.run(state_ptrs, fitness.frames);
  for (std::size_t k = 0; k < models.size(); ++k) results[index[k]] = score_run(models[k], states[k], start[k], fitness);
  return results;
}

Evaluation evaluate_prepared(const soda::ModelDef& prepared, const FitnessConfig& fitness) {
  return evaluate_prepared_batch({&prepared}, fitness).front();
}


Evaluation evaluate_prepared_with(const soda::ModelDef& prepared, const FitnessConfig& fitness,
                                  const soda::Stepping& stepping) {
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
  soda::FrameStepper stepper(model, stepping, fitness.settle_frames + fitness.frames);
  const bool energy = fitness.divergence == DivergenceCheck::Energy;
  soda::DivergenceMonitor monitor(model, state, {}, energy);
  const long long total = fitness.settle_frames + fitness.frames;
  soda::Point2 start = soda::mass_centroid(model, state);
  for (long long done = 0; done < total;) {
    if (done == fitness.settle_frames) start = soda::mass_centroid(model, state);
    long long n = energy ? 1 : kFiniteCheckInterval;
    if (done < fitness.settle_frames) n = std::min(n, fitness.settle_frames - done);
    n = std::min(n, total - done);
    stepper.run(state, n);
    done += n;
    if (!monitor.check(state)) {
      e.status = EvaluationStatus::Diverged;
      e.reason = monitor.result().reason + " (by frame " + std::to_string(monitor.result().frame) + ")";
      return e;
    }
  }
  return score_distance(start, soda::mass_centroid(model, state), fitness);
}

namespace {

Evaluation evaluate_watched(const soda::ModelDef& prepared, const FitnessConfig& fitness) {
  Evaluation e = evaluate_prepared_with(prepared, fitness, fitness.stepping());
  if (!e.ok() || !(fitness.honesty_max_change > 0.0)) return e;
  const soda::Stepping refined = refined_stepping(fitness.stepping(), fitness.honesty_substeps_factor);
  const Evaluation r = evaluate_prepared_with(prepared, fitness, refined);
  if (!r.ok()) {
    Evaluation flagged;
    flagged.status = EvaluationStatus::Diverged;
    flagged.reason = "dishonest: with " + soda::stepping_label(refined) + " it " + r.reason;
    return flagged;
  }
  e.honesty_change = relative_change(e.distance, r.distance);
  if (std::fabs(e.honesty_change) > fitness.honesty_max_change) {
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

} // namespace


std::optional<soda::ModelDef> prepare_creature(const soda::ModelDef& creature, const RunConfig& config,
                                               std::string& why) {
  if (std::optional<std::string> invalid = check_creature(creature, config.limits)) {
    why = "creature " + *invalid;
    return std::nullopt;
  }
  try {
    return prepare_for_evaluation(creature, config.fitness, config.world);
  } catch (const std::exception& ex) {
    why = ex.what();
    return std::nullopt;
  }
}

std::vector<Evaluation> evaluate_creature_batch(const std::vector<const soda::ModelDef*>& creatures,
                                                const RunConfig& config) {
  std::vector<Evaluation> results(creatures.size());
  std::vector<soda::ModelDef> prepared;
  prepared.reserve(creatures.size());
  std::vector<std::size_t> index; // result index of prepared[k]
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    if (std::optional<soda::ModelDef> p = prepare_creature(*creatures[i], config, results[i].reason)) {
      prepared.push_back(std::move(*p));
      index.push_back(i);
    }
  }
  std::vector<const soda::ModelDef*> ptrs;
  for (const soda::ModelDef& p : prepared) ptrs.push_back(&p);
  std::vector<Evaluation> scored;
  try {
    scored = evaluate_prepared_batch(ptrs, config.fitness);
  } catch (const std::exception& ex) {
    for (std::size_t k = 0; k < prepared.size(); ++k) results[index[k]].reason = ex.what();
    return results;
  }
  for (std::size_t k = 0; k < prepared.size(); ++k) results[index[k]] = std::move(scored[k]);
  return results;
}

Evaluation evaluate_creature(const soda::ModelDef& creature, const RunConfig& config) {
  return evaluate_creature_batch({&creature}, config).front();
}

} // namespace sodaevo
