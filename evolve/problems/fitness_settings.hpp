// FitnessConfig: the /fitness object of a run config (configs/README.md), the
// settings a Problem is constructed from (what is scored, over how many frames,
// in which stepping) together with the Estimator's (replicas, statistic, jitter),
// as the file format groups them. config/run_config.cpp reads it.
#pragma once

#include <string>

#include "core/enum_names.hpp"
#include "core/stepping.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/problems/race_settings.hpp"

namespace sodaevo {

enum class WalkDirection { Right, Left, Either };
enum class FitnessScaling { None, Sodarace };
/// What counts as diverged (core/divergence.hpp): only non-finite numbers, or also
/// runaway energy beyond what the muscles can supply.
enum class DivergenceCheck { Finite, Energy };
/// The statistic of a creature's replicas that is its fitness
/// (evolve/estimators/replica_estimator.hpp): their mean, their median, or the lower end of
/// the 95 % confidence interval of their mean.
enum class EstimateStatistic { Mean, Median, LowerBound };

/// The JSON spellings of the enums above (core/enum_names.hpp).
inline constexpr soda::EnumName<WalkDirection> kWalkDirectionNames[] = {
    {WalkDirection::Right, "right"}, {WalkDirection::Left, "left"}, {WalkDirection::Either, "either"}};
inline constexpr soda::EnumName<FitnessScaling> kFitnessScalingNames[] = {{FitnessScaling::Sodarace, "sodarace"},
                                                                         {FitnessScaling::None, "none"}};
inline constexpr soda::EnumName<DivergenceCheck> kDivergenceCheckNames[] = {{DivergenceCheck::Finite, "finite"},
                                                                           {DivergenceCheck::Energy, "energy"}};
inline constexpr soda::EnumName<EstimateStatistic> kEstimateStatisticNames[] = {
    {EstimateStatistic::Mean, "mean"}, {EstimateStatistic::Median, "median"}, {EstimateStatistic::LowerBound, "lcb"}};
inline std::string direction_name(WalkDirection d) { return soda::name_of(kWalkDirectionNames, d); }
inline std::string scaling_name(FitnessScaling s) { return soda::name_of(kFitnessScalingNames, s); }
inline std::string divergence_check_name(DivergenceCheck d) { return soda::name_of(kDivergenceCheckNames, d); }
inline std::string statistic_name(EstimateStatistic s) { return soda::name_of(kEstimateStatisticNames, s); }

/// How a creature is scored: the distance walked by the centroid, or a race
/// (configs/README.md, /fitness).
struct FitnessConfig {
  FitnessKind kind = FitnessKind::Walk; ///< /fitness/kind: "walk" | "race"
  RaceFitnessConfig race;               ///< /fitness/race: only with kind "race"
  long long frames = 2000;        ///< /fitness/frames: scored frames, [1, 1e7]
  long long settle_frames = 200;  ///< /fitness/settle_frames: unscored frames first, [0, 1e7]
  WalkDirection direction = WalkDirection::Right; ///< /fitness/direction: "right" | "left" | "either"
  /// /fitness/scaling: "sodarace" scales the creature as the Sodarace racer did
  /// (configs/README.md, /fitness/scaling: s = 211/sqrt(sum Lmax^2), positions, rest lengths,
  /// velocities and gravity times s) so that growing is no way to win; "none" leaves it.
  FitnessScaling scaling = FitnessScaling::Sodarace;
  double drop_height = 5.0;       ///< /fitness/drop_height: lowest mass placed this high, px, [0, 1000]
  /// /fitness/mode, /fitness/integrator, /fitness/substeps: how the physics is
  /// stepped (core/stepping.hpp); default the original's one update per frame.
  soda::PhysicsMode mode = soda::PhysicsMode::Soda;
  soda::Integrator integrator = soda::Integrator::Euler;
  int substeps = 1;               ///< [1, 4096], continuous mode only
  DivergenceCheck divergence = DivergenceCheck::Finite; ///< /fitness/divergence: "finite" | "energy"
  /// /fitness/honesty/max_change: flag (as diverged) a creature whose distance
  /// changes by more than this share when re-evaluated with
  /// /fitness/honesty/substeps_factor times the sub-steps (evolve/problems/honesty.hpp);
  /// 0 = no check. [0, 1e6]
  double honesty_max_change = 0.0;
  int honesty_substeps_factor = 4; ///< /fitness/honesty/substeps_factor [2, 64]
  /// /fitness/replicas: rollouts per new creature, replica 0 exact and the others
  /// with their own sine jitter (core/sine_jitter.hpp), [1, 256].
  int replicas = 8;
  /// /fitness/replicas_max: the creatures that survive a generation (the elites)
  /// gather /fitness/replicas more each generation up to this many,
  /// [replicas, 1024].
  int replicas_max = 32;
  /// /fitness/confirm: when the run ends, its best this many creatures are
  /// estimated again on replicas_max replicas each (ranked again until the best
  /// this many all are), so that what the run hands over is not its luckiest
  /// draws (evolve/evaluators/evaluator.hpp, confirm_best). 0 = off. [0, 100000]
  int confirm = 10;
  EstimateStatistic statistic = EstimateStatistic::Mean; ///< /fitness/statistic: "mean" | "median" | "lcb"
  double jitter = 0.002; ///< /fitness/jitter: share of sines a jittered replica moves by 1 ulp, [0, 1]
  /// /fitness/stability_margin_min: refuse (as invalid, with the reason) a creature
  /// whose predicted stability margin of the step (core/stability.hpp, at its
  /// prepared start, in this stepping) is below this: a guard against walks that
  /// are an integration instability. 0 = no check. [0, 1e6]
  double stability_margin_min = 0.0;

  [[nodiscard]] soda::Stepping stepping() const { return {mode, integrator, substeps}; }

  bool operator==(const FitnessConfig&) const = default;
};

} // namespace sodaevo
