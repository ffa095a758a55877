#include "honesty.hpp"

#include <algorithm>
#include <cmath>

namespace sodaevo {

soda::Stepping refined_stepping(const soda::Stepping& s, int factor) {
  soda::Stepping r = s;
  if (s.mode == soda::PhysicsMode::Soda) {
    r.mode = soda::PhysicsMode::Continuous;
    r.integrator = soda::Integrator::Euler;
    r.substeps = std::min(factor, soda::kMaxSubsteps);
    return r;
  }
  const long long substeps = static_cast<long long>(s.substeps) * factor;
  r.substeps = static_cast<int>(std::min<long long>(substeps, soda::kMaxSubsteps));
  return r;
}

double relative_change(double distance, double refined_distance) {
  return (refined_distance - distance) / std::max(std::fabs(refined_distance), kHonestyDistanceFloor);
}

} // namespace sodaevo
