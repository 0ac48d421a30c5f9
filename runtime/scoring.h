#ifndef SPLAM_RUNTIME_SCORING_H_
#define SPLAM_RUNTIME_SCORING_H_

#include <cstddef>
#include <vector>

#include "estimation/map_spline.h"
#include "sim/ray_caster.h"

// How runs are scored: map accuracy against the simulator's truth, and timing statistics.
namespace splam::runtime {

// The q-quantile (0..1) of v by nth_element; 0 for an empty v.
double Percentile(std::vector<double> v, double q);

// The median time per step in one bin of the map size.
struct TimeBin {
  std::size_t map_size_from = 0, map_size_to = 0;  // inclusive
  std::size_t steps = 0;
  double median_ms = 0.0;
};
// Median time per step in 8 equal bins of the map size (landmarks, control points or curves);
// empty bins are left out.
std::vector<TimeBin> TimeByMapSize(const std::vector<double>& ms,
                                   const std::vector<std::size_t>& map_size);

// Map accuracy: the mean distance from points 5 cm apart along the map curves to the nearest true
// obstacle (capped at 2 m), metres; 0 for an empty map.
double MeanDistanceToObstacles(const sim::RayCaster& caster,
                               const std::vector<estimation::MapSpline>& splines);

// Map curves per true obstacle: every map curve is given to the obstacle
// nearest to most of its points (5 cm apart, within 0.5 m); the number of curves over the number
// of obstacles given at least one. A map that builds an object twice, or in pieces, scores more
// than 1; curves on no obstacle count in the numerator only. 0 for an empty map.
double CurvesPerObstacle(const sim::RayCaster& caster,
                         const std::vector<estimation::MapSpline>& splines);

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_SCORING_H_
