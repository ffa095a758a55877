#include "evolve/problems/race_progress.hpp"

#include <algorithm>
#include <cmath>

namespace sodaevo {

double track_progress(const soda::RaceLane& lane, double start_min_x, double furthest_min_x) {
  const double line = lane.finish_x + 6.0;
  const double way = line - start_min_x;
  if (!std::isfinite(furthest_min_x) || !std::isfinite(start_min_x) || !(way > 0.0)) return 0.0;
  return std::clamp((furthest_min_x - start_min_x) / way, 0.0, 1.0);
}

double progress_cost(const std::vector<TerrainRaceResult>& races) {
  double weight = 1.0, sum = 0.0;
  int unfinished = 0;
  for (const TerrainRaceResult& r : races) {
    const double limit = static_cast<double>(r.timeout) + 1.0;
    weight += 2.0 * limit;
    if (r.finished) {
      sum += r.result;
    } else {
      ++unfinished;
      sum += limit * (2.0 - std::clamp(r.progress, 0.0, 1.0));
    }
  }
  return static_cast<double>(unfinished) * weight + sum;
}

} // namespace sodaevo
