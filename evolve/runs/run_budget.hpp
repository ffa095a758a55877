// The skeleton both run loops share (evolution_run.cpp: the GA's generations;
// map_elites_run.cpp: MAP-Elites' iterations): a wall clock that carries over
// resumes, and the one rule that says, before each step, whether the run stops
// and why. Each loop knows what its next step costs; the rule's order is theirs
// alike: the planned steps, the evaluation budget, the wall-time budget, a stop
// asked for (Ctrl-C).
#pragma once

#include <atomic>
#include <chrono>
#include <optional>
#include <string>

#include "core/enum_names.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo {

enum class StopReason { Completed, EvaluationBudget, WallTimeBudget, Interrupted };
inline constexpr soda::EnumName<StopReason> kStopReasonNames[] = {{StopReason::Completed, "completed"},
                                                                 {StopReason::EvaluationBudget, "evaluation budget"},
                                                                 {StopReason::WallTimeBudget, "wall-time budget"},
                                                                 {StopReason::Interrupted, "interrupted"}};
inline std::string stop_reason_name(StopReason r) { return soda::name_of(kStopReasonNames, r); }

/// A run's wall-clock seconds, resumes included: what its checkpoint held plus
/// the time since this process took it up.
class RunClock {
 public:
  explicit RunClock(double previous_seconds = 0.0)
      : previous_(previous_seconds), started_(std::chrono::steady_clock::now()) {}
  /// Counts on from a checkpoint's seconds (the clock keeps its start).
  void carry_over(double previous_seconds) { previous_ = previous_seconds; }
  [[nodiscard]] double seconds() const {
    return previous_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  }

 private:
  double previous_;
  std::chrono::steady_clock::time_point started_;
};

/// Why the run stops before its next step, or nullopt to take it: `planned_done`
/// (its generations or iterations are done), `no_room` (the evaluation budget
/// cannot pay for the next step), /budget/wall_seconds spent, `stop_requested`.
inline std::optional<StopReason> stop_before_next_step(bool planned_done, bool no_room, const BudgetConfig& budget,
                                                       const RunClock& clock,
                                                       const std::atomic<bool>* stop_requested) {
  if (planned_done) return StopReason::Completed;
  if (no_room) return StopReason::EvaluationBudget;
  if (budget.max_wall_seconds > 0 && clock.seconds() >= budget.max_wall_seconds) return StopReason::WallTimeBudget;
  if (stop_requested != nullptr && stop_requested->load()) return StopReason::Interrupted;
  return std::nullopt;
}

} // namespace sodaevo
