// The golden race results of the original racer (races.tsv of the golden terrain
// data: 20 public race files x 44 contenders), raced again with core/race_lane.hpp.
//
// The report measures, on our own runs, the situations that the bar rules inferred
// from these races decide (BarMemory's counters: a remembered mass starting far from
// the bar's line, a crossing point just beyond a bar's end, a concave joint past the
// next bar's far end): how many races meet each, and in the races a rule was
// inferred from and in any race that differs, the first frame our run meets it.
// Beside the measurements, a short table of diagnoses (what was found in those
// races by hand) says which situation explains which contender.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sodaevo::bench {

/// The situations the inferred bar rules decide (fixed_bars.hpp, BarMemory's counters).
enum class BarSituation { FarStart, NearEndMiss, FarEndCorner };
inline constexpr int kBarSituations = 3;
/// "far start" | "near-end miss" | "far-end corner"
const char* bar_situation_name(BarSituation s);

/// A diagnosis made by hand (not a measurement): the situation that explained a
/// contender's race, the rule that decides it and what happens there.
struct RaceDiagnosis {
  const char* contender; ///< file name without .xml
  BarSituation situation;
  const char* rule;      ///< the rule in fixed_bars.hpp
  const char* what;
};
/// The diagnoses of the races the inferred rules came from (all on TerrainAi).
const std::vector<RaceDiagnosis>& race_diagnoses();

struct GoldenRace {
  std::string race, contender; ///< as races.tsv names them
  double golden = 0.0;         ///< the original's result
  double ours = 0.0;
  bool ours_finished = false;
  /// Per BarSituation: how often our race met it (its final state's counters).
  long long situations[kBarSituations] = {0, 0, 0};
  /// Per BarSituation: the first update at which our race met it, -1: never or not
  /// watched (watched, frame by frame, in races that differ and in the diagnosed
  /// contenders' races).
  long long first_update[kBarSituations] = {-1, -1, -1};
  [[nodiscard]] bool same() const { return golden == ours; }
};

/// Reads races.tsv in `data`/terrain (paths under shared/models/soda/ are looked up in
/// `data`/soda and `data`/terrain) and races the rows whose race file name contains
/// `race_filter` and whose contender contains `contender_filter` (empty: all).
std::vector<GoldenRace> race_golden(const std::filesystem::path& data, const std::string& race_filter = "",
                                    const std::string& contender_filter = "");

/// A Markdown report: counts per race file, the situations of the inferred rules
/// as measured, every difference with what was measured in it and its diagnosis.
std::string golden_races_report(const std::vector<GoldenRace>& races);

} // namespace sodaevo::bench

namespace sodaevo::bench {

/// Lane speed: frames per second of one creature in a race lane (the FastStepper,
/// bars tested) and of the same lane model without its bars (the creature on the
/// container's floor), each the best of `repeats` runs of `frames` frames.
struct LaneSpeed {
  double lane_fps = 0.0;
  double floor_fps = 0.0;
  double ordered_fps = 0.0;      ///< the lane with every mass one by one in file order (force_ordered)
  double rules_per_frame = 0.0;  ///< masses that took the bar rules per frame (FastStepper::bar_rules_run)
  int masses = 0;
  [[nodiscard]] double ratio() const { return floor_fps > 0.0 ? lane_fps / floor_fps : 0.0; }
  /// Nanoseconds per frame the lane costs more than the floor.
  [[nodiscard]] double extra_ns() const { return lane_fps > 0.0 && floor_fps > 0.0 ? 1e9 / lane_fps - 1e9 / floor_fps : 0.0; }
};
LaneSpeed measure_lane_speed(const std::filesystem::path& race_file, const std::filesystem::path& contender,
                             long long frames, int repeats);

/// Fused lanes: the contenders in `contenders_dir`, each in its own lane of
/// `race_file`, stepped one by one (a FastStepper each) and together (BatchStepper:
/// fused scenes), with the lanes' bars and without them; and their races, one by one
/// (run_race_fast) and together (run_races_together). Each figure the best of
/// `repeats` alternated runs.
struct FusedLaneSpeed {
  int lanes = 0;
  double alone_fps = 0.0, fused_fps = 0.0;             ///< lane-frames per second, with bars
  double floor_alone_fps = 0.0, floor_fused_fps = 0.0; ///< the same lane models without their bars
  double races_alone_s = 0.0, races_fused_s = 0.0;     ///< seconds for all the races
  long long race_frames = 0;                           ///< updates of all the races
};
FusedLaneSpeed measure_fused_lanes(const std::filesystem::path& race_file, const std::filesystem::path& contenders_dir,
                                   long long frames, int repeats);

} // namespace sodaevo::bench
