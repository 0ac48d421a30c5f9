#ifndef SPLAM_TESTS_ESTIMATION_MAP_ERROR_H_
#define SPLAM_TESTS_ESTIMATION_MAP_ERROR_H_

#include <vector>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "sim/ray_caster.h"
#include "sim/world.h"

namespace splam::estimation::test_util {

// Mean distance from points every 5 cm along the map curves to the nearest true obstacle, each
// capped at 1 m; 1 m for an empty map.
inline double MapError(const sim::World& world, const std::vector<MapSpline>& map) {
  const sim::RayCaster caster(world);
  double sum = 0.0;
  int n = 0;
  for (const MapSpline& s : map) {
    for (const Eigen::Vector2d& p : s.spline.ResampleByArcLength(0.05)) {
      const sim::RayHit near = caster.Nearest(p, 1.0);
      sum += near.obstacle >= 0 ? near.range_m : 1.0;
      ++n;
    }
  }
  return n > 0 ? sum / n : 1.0;
}

}  // namespace splam::estimation::test_util

#endif  // SPLAM_TESTS_ESTIMATION_MAP_ERROR_H_
