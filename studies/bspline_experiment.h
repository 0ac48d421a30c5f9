#ifndef SPLAM_STUDIES_BSPLINE_EXPERIMENT_H_
#define SPLAM_STUDIES_BSPLINE_EXPERIMENT_H_

#include <cstdint>
#include <functional>
#include <string>

#include "io/sweep_grid.h"

namespace splam::studies {

// complex-bspline (paper 000 Figs. 15-17): EKF-SLAM with B-splines in the `complex` world along
// its built-in route with a URG-04LX, once with Pedraza's association and once with paper 000's
// curvature association, over `runs` seeds. Writes x, y, theta errors over time (odometry and
// both associations), a table (position and heading RMSE, maximum error, map accuracy as the
// mean distance from the map curves to the true obstacles, wrong associations counted with the
// simulator's record of which obstacle each beam hit, time per scan) and the maps. One seed runs
// in this process; several are the cells of a grid (ComplexBSplineGrid: this experiment with
// --runs 1 per seed) on the sweep engine, `jobs` at once, `out` its sweep directory.
struct BSplineExperimentArgs {
  int runs = 10;
  std::uint64_t seed = 1;
  int max_scans = 0;  // 0: the whole route
  // Scale of the simulator's odometry noise (and of the filter's model of it): a harder test of
  // the associations, whose predicted curves then land farther from the observed ones.
  double odometry_noise_scale = 1.0;
  // The correspondence test of every beam (EkfBSplineSlamOptions::max_correspondence_distance_m);
  // a large value switches it off, leaving the association's stretches unchecked.
  double max_correspondence_distance_m = 0.15;
  // Which matches correct the state (EkfBSplineSlamOptions::match_selection): longest or jcbb.
  std::string match_selection = "longest";
  // A built-in world with a route (`curves`: obstacles rich in curvature features).
  std::string world = "complex";
  std::string out = "runs/experiment-complex-bspline";
  std::string splam_binary = "splam";  // what runs the cells
  int jobs = 0;                        // cells at once; 0: one per core
  std::function<bool()> stop;          // Ctrl-C: finished seeds stay, the rest run next time
};
io::Grid ComplexBSplineGrid(const BSplineExperimentArgs& args);
int RunComplexBSpline(const BSplineExperimentArgs& args);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_BSPLINE_EXPERIMENT_H_
