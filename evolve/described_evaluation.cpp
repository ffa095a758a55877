#include "described_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "core/batch_step.hpp"
#include "core/input_error.hpp"
#include "evolve/walk_problem.hpp"

namespace sodaevo {

namespace {

/// The score of a finished rollout, as fitness.cpp's score_run gives it.
Evaluation score_rollout(const soda::Model& model, const soda::State& state, soda::Point2 start,
                         const FitnessConfig& fitness) {
  Evaluation e;
  for (int i = 0; i < model.mass_count; ++i) {
    if (!std::isfinite(state.x[i]) || !std::isfinite(state.y[i]) || !std::isfinite(state.vx[i]) ||
        !std::isfinite(state.vy[i])) {
      e.status = EvaluationStatus::Diverged;
      e.reason = "non-finite state of mass " + std::to_string(i) + " at frame " + std::to_string(state.frame);
      return e;
    }
  }
  e.distance = soda::mass_centroid(model, state).x - start.x;
  e.px_per_frame = e.distance / static_cast<double>(fitness.frames);
  switch (fitness.direction) {
    case WalkDirection::Right: e.fitness = e.distance; break;
    case WalkDirection::Left: e.fitness = -e.distance; break;
    case WalkDirection::Either: e.fitness = std::fabs(e.distance); break;
  }
  e.status = EvaluationStatus::Ok;
  return e;
}

} // namespace

std::vector<DescribedEvaluation> evaluate_described_batch(const std::vector<const soda::ModelDef*>& prepared,
                                                          const FitnessConfig& fitness, long long sample_every) {
  if (fitness.mode != soda::PhysicsMode::Soda || fitness.divergence != DivergenceCheck::Finite ||
      fitness.honesty_max_change > 0.0) {
    throw soda::InputError("descriptors are measured only with /fitness/mode \"soda\", /fitness/divergence "
                           "\"finite\" and /fitness/honesty/max_change 0");
  }
  if (sample_every < 1) throw soda::InputError("descriptor sample interval must be at least 1 frame");
  std::vector<DescribedEvaluation> results(prepared.size());
  std::vector<soda::Model> models;
  models.reserve(prepared.size());
  std::vector<std::size_t> index; // result index of models[k]
  for (std::size_t i = 0; i < prepared.size(); ++i) {
    try {
      models.push_back(soda::build_model(*prepared[i]));
      index.push_back(i);
    } catch (const std::exception& ex) {
      results[i].evaluation.reason = ex.what();
    }
  }
  if (models.empty()) return results;
  std::vector<const soda::Model*> model_ptrs;
  std::vector<soda::State> states;
  std::vector<DescriptorMeter> meters;
  for (const soda::Model& m : models) {
    model_ptrs.push_back(&m);
    states.push_back(soda::make_state(m));
    meters.emplace_back(m);
  }
  std::vector<soda::State*> state_ptrs;
  for (soda::State& s : states) state_ptrs.push_back(&s);
  // Stepping in chunks gives the bits of one long run (BatchStepper::run equals
  // soda::run frame for frame), so the fitness is evaluate_prepared_batch's.
  soda::BatchStepper stepper(model_ptrs, static_cast<long long>(fitness.settle_frames) + fitness.frames);
  stepper.run(state_ptrs, fitness.settle_frames);
  std::vector<soda::Point2> start;
  for (std::size_t k = 0; k < models.size(); ++k) start.push_back(soda::mass_centroid(models[k], states[k]));
  for (long long done = 0; done < fitness.frames;) {
    const long long n = std::min(sample_every, fitness.frames - done);
    stepper.run(state_ptrs, n);
    done += n;
    for (std::size_t k = 0; k < models.size(); ++k) meters[k].observe(states[k]);
  }
  for (std::size_t k = 0; k < models.size(); ++k) {
    DescribedEvaluation& r = results[index[k]];
    r.evaluation = score_rollout(models[k], states[k], start[k], fitness);
    if (r.evaluation.ok()) r.behaviour = meters[k].behaviour();
  }
  return results;
}

std::vector<DescribedEvaluation> evaluate_described_creatures(const std::vector<const soda::ModelDef*>& creatures,
                                                              const RunConfig& config, long long sample_every) {
  std::vector<DescribedEvaluation> results(creatures.size());
  const WalkProblem problem(config);
  std::vector<soda::ModelDef> prepared;
  prepared.reserve(creatures.size());
  std::vector<std::size_t> index; // result index of prepared[k]
  for (std::size_t i = 0; i < creatures.size(); ++i) {
    try {
      prepared.push_back(problem.prepare(*creatures[i]));
      index.push_back(i);
    } catch (const std::exception& ex) {
      results[i].evaluation.reason = ex.what();
    }
  }
  std::vector<const soda::ModelDef*> ptrs;
  for (const soda::ModelDef& p : prepared) ptrs.push_back(&p);
  std::vector<DescribedEvaluation> scored = evaluate_described_batch(ptrs, config.fitness, sample_every);
  for (std::size_t k = 0; k < prepared.size(); ++k) results[index[k]] = std::move(scored[k]);
  return results;
}

} // namespace sodaevo
