#ifndef SPLAM_ESTIMATION_POSE_GRAPH_CORRELATIVE_MATCHER_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_CORRELATIVE_MATCHER_H_

#include <Eigen/Core>
#include <vector>

#include "estimation/pose_graph/distance_grid.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

namespace splam::estimation {

// Multi-resolution correlative search (Olson 2009) by branch and bound (Hess et al. 2016): the
// pose in a window around a guess that maximises the mean likelihood of the points on a
// LikelihoodPyramid. It needs no good initial guess inside its window, so loop closures use it.
struct CorrelativeOptions {
  // 0: the step that moves the 90 % farthest point by a cell; a step below a sixteenth of that is
  // raised to it.
  double angular_step_rad = 0.0;
  // A second peak counts as distinct from the best when it is this far from it (m or rad).
  double distinct_m = 0.5;
  double distinct_rad = 0.2;
};

struct CorrelativeMatch {
  bool found = false;         // a pose with a score above min_score
  kernel::Pose2 pose;         // world_T_points of the best pose
  double score = 0.0;         // its mean likelihood, in [0, 1]
  double second_score = 0.0;  // the best distinct pose's score (0: none above min_score)
  kernel::Pose2 second_pose;  // that pose, when second_score > 0
  long evaluated = 0;         // score evaluations (cost)
};

// Searches translations within +- linear_window_m and headings within +- angular_window_rad of
// `guess` (world_T_points) for poses whose score is at least min_score; the second-best distinct
// pose is searched down to ratio_floor times the best. Points are in their own frame.
CorrelativeMatch SearchCorrelative(const std::vector<Eigen::Vector2d>& points,
                                   const LikelihoodPyramid& map, const kernel::Pose2& guess,
                                   double linear_window_m, double angular_window_rad,
                                   double min_score, double ratio_floor,
                                   const CorrelativeOptions& options = {});

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_CORRELATIVE_MATCHER_H_
