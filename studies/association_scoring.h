#ifndef SPLAM_STUDIES_ASSOCIATION_SCORING_H_
#define SPLAM_STUDIES_ASSOCIATION_SCORING_H_

#include <map>
#include <string>
#include <vector>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "kernel/trajectory.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

// Paper 000 Figs. 15-17 on the simulator (`splam experiment complex-bspline`): the B-spline EKF
// with either association along a simulated route, its associations judged against the
// simulator's record of which obstacle every beam hit.
namespace splam::studies {

// How many of the beams hit each obstacle (-1: none).
std::map<int, int> Votes(const std::vector<std::size_t>& beams, const std::vector<int>& obstacles);
// The obstacle most of the beams hit (the lowest index on a tie; -1 for no beams).
int MajorityObstacle(const std::vector<std::size_t>& beams, const std::vector<int>& obstacles);

struct AssociationRun {
  kernel::Trajectory estimate;
  std::vector<estimation::MapSpline> map;
  // An association (an accepted match, whether or not its beams then passed the correspondence
  // test and the gate) is wrong when most of its stretch's beams hit an obstacle the map spline
  // was not made from; a beam is wrong when it hit such an obstacle.
  int associations = 0, wrong_associations = 0, with_features = 0;
  long beams = 0, wrong_beams = 0;
  double mean_nees = 0.0;    // of the pose, over the run
  double map_error_m = 0.0;  // mean distance of map curve points to the nearest obstacle
  double ms_per_scan = 0.0;
  bool healthy = true;
  std::string failure;  // why the filter stopped (its health message) when not healthy
};

// The filter over the frames of a simulated route (whose beam_obstacles are filled), scored.
AssociationRun RunBSplineFilter(const std::vector<sim::SensorFrame>& frames,
                                const sim::RayCaster& caster,
                                const estimation::EkfBSplineSlamOptions& options);

}  // namespace splam::studies

#endif  // SPLAM_STUDIES_ASSOCIATION_SCORING_H_
