// Motion: a creature's movement pre-computed by the engine, for pictures and players.
//
// The renderer never moves anything itself: record_motion() builds the Model from
// the ModelDef and runs the engine in the chosen physics mode (soda by default: the
// FastStepper, bit for bit the reference step; a run's report uses its fitness
// mode, so the players show the motion that was scored), keeping every k-th frame. Positions are kept rounded to 0.1 px - plenty for a picture,
// and it keeps the animations embedded in HTML pages small.
#pragma once

#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/model_def.hpp"
#include "core/race_lane.hpp"
#include "core/stepping.hpp"

namespace sodaevo::app {

struct MotionLink {
  int a = 0, b = 0;          ///< point indices: masses [0, masses), then fixed nodes
  soda::LinkKind kind = soda::LinkKind::Spring;
  double rest = 0.0;         ///< rest length (springs and muscles), px
};

/// A vertical line the player draws at x (e.g. a race's start and finish).
struct MotionMark {
  double x = 0.0;
  std::string label;
};

struct Motion {
  std::string name;
  int masses = 0;
  std::vector<double> fixed_xy;       ///< fixed nodes, x y pairs (they never move)
  std::vector<MotionLink> links;      ///< springs, muscles, then fixed bars
  double width = 0.0, height = 0.0;   ///< container: walls at x = 0 and width, floor y = 0, ceiling y = height
  long long frames = 0;               ///< frames simulated
  int every = 1;                      ///< a sample every `every` frames (and the last frame)
  std::vector<long long> sample_frames;     ///< frame number of each sample, from 0
  std::vector<std::vector<double>> mass_xy; ///< per sample: x0 y0 x1 y1 ... of the masses, rounded to 0.1 px
  std::vector<double> centroid_x;           ///< per sample: mean x of the masses (not rounded); of the fixed nodes if there are no masses
  std::vector<MotionMark> marks;            ///< lines to draw (races: start, finish)
  /// Non-empty if the state became non-finite: the recording stops before it.
  std::string diverged;

  [[nodiscard]] std::size_t samples() const { return sample_frames.size(); }
  /// Centroid x of the last sample minus that of the first, px.
  [[nodiscard]] double distance() const { return centroid_x.empty() ? 0.0 : centroid_x.back() - centroid_x.front(); }
};

/// The sample interval that keeps at most `max_samples` samples of `frames` frames.
int sample_interval(long long frames, int max_samples);

/// A Motion with `model`'s constant parts (container, fixed nodes, links) and no samples.
Motion motion_of_model(const soda::Model& model, const std::string& name);

/// Runs `def` (as loaded: its own world and container) for `frames` frames and
/// keeps frame 0, every `every`-th frame and the last. Throws soda::InputError if
/// the model is not valid.
Motion record_motion(const soda::ModelDef& def, long long frames, int every, const soda::Stepping& stepping = {});

/// A race in its lane (core/race_lane.hpp) to its finish or `timeout`, with the
/// reference runner, at most `max_samples` samples; the start and finish lines as
/// marks. The frame count is the race's, known only once it is run, so the whole
/// race is recorded and then sampled.
Motion record_race_motion(const soda::RaceLane& lane, const soda::Model& model, int timeout, const std::string& name,
                          int max_samples = 2000);

/// record_race_motion of `contender` (as the racer reads a contender file) in its
/// lane on `race`'s terrain. Throws soda::InputError for a contender the lane refuses.
Motion record_race_motion(const soda::RaceDef& race, int timeout, const soda::ModelDef& contender,
                          const std::string& name, int max_samples = 2000);

} // namespace sodaevo::app
