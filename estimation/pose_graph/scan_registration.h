#ifndef SPLAM_ESTIMATION_POSE_GRAPH_SCAN_REGISTRATION_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_SCAN_REGISTRATION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "estimation/pose_graph/distance_grid.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

namespace splam::estimation {

// Scan-to-submap registration (front end of the graph SLAM, after Hess et al. 2016): the pose
// T = (x, y, theta) minimising
//   sum_i rho(D(T p_i)^2 / sigma^2) + |W (prior^-1 T)|^2
// where D is the submap's distance to its nearest outline piece (DistanceGrid::Distance, exact
// within a cell) or, as in Hess et al., its field interpolated bicubically
// (ceres::BiCubicInterpolator), p_i the scan's points in the robot frame, rho a Huber loss and W
// the prior's square-root information (the odometry increment's uncertainty).
struct RegistrationOptions {
  double point_sigma_m = 0.03;  // the distance residual's scale, m
  // The bicubic interpolation of an unsigned field at 0.1 m cells moves its valley off the
  // outline by up to a few cm depending on where the outline crosses the cells, a bias that
  // changes with every new submap; the grid's exact distance to the nearest outline piece has no
  // such bias (measured in docs/graph_slam.md). false: the exact distance.
  bool bicubic_field = false;
  // Beyond loss_scale_m farther points count linearly (Huber) or, with cauchy_loss, their pull
  // fades (Cauchy).
  bool cauchy_loss = false;
  double loss_scale_m = 0.1;     // m
  double prior_sigma_m = 0.1;    // prior on the translation, m
  double prior_sigma_rad = 0.1;  // prior on the heading, rad
  int max_iterations = 20;
  // Points where the map has not seen (DistanceGrid::Known) carry no residual. Quality test: at
  // least min_points points where the map has seen; points within inlier_distance_m of the map
  // make up at least min_inlier_fraction of all the points (a scan mostly outside what the map
  // saw is not trusted); the result moved from the prior by at most max_correction_m /
  // max_correction_rad.
  double inlier_distance_m = 0.1;
  double min_inlier_fraction = 0.5;
  int min_points = 20;
  double max_correction_m = 0.3;
  double max_correction_rad = 0.2;
  // Outline ends: a point that lies past the end of its nearest outline piece (along the
  // piece, beyond the 1.5 cells either side of its cell that overlap the neighbouring pieces of a
  // continuous outline), where the map did not see free space (DistanceGrid::SeenFree: only the
  // margin behind its hits), carries no residual: the outline the map saw ends there, and the
  // point is on a part it has not seen (the rest of a pillar round from its silhouette, a wall
  // going on past a corner). Matched, such points were pulled to the end of the piece's straight
  // extension and turned loop closures on `complex` by 0.7-1.1 deg (docs/graph_slam.md). Where
  // the map saw free space (a doorway) the point stays: evidence against the pose; without that
  // exception a corridor's closures slid 0.7 m along it in `office` explorations.
  bool skip_past_outline_ends = true;
  // Normal compatibility: a point whose free side (its normal, towards the sensor that saw it)
  // is turned from that of its nearest outline piece by more than max_normal_angle_rad (at the
  // prior) carries no residual either: it lies on a side of an object the map has not seen (the
  // far side of a pillar near the silhouette the map saw, the back of a thin wall), where the
  // nearest piece belongs to another surface and would pull the scan askew. Points or pieces
  // without a normal are always matched; pi disables the test. 1 rad: the normals of one
  // surface, fitted over 0.3 m of a URG's noise or turning along a pillar's piece, stay well
  // within it; tighter refuses good points (docs/graph_slam.md).
  double max_normal_angle_rad = 1.0;
  // Where the map saw an outline from both sides (DistanceGrid::BackNormal: a thin wall, a door's
  // leaf), a point facing either side is matched. One normal per cell showed only the side seen
  // more often: leaving a room into a corridor along its wall (zero-thick in the simulator), half
  // of every scan faced away from the room side and went unmatched, the registration failed its
  // inlier test, and the recovery search pulled the robot back 0.3 m every few scans while it
  // drove 4 m (`office` exploration, REG + graph, seed 8; docs/graph_slam.md).
  bool two_sided_outlines = true;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

struct RegistrationResult {
  kernel::Pose2 pose;                                        // the registered pose
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // (J^T J)^-1 at the solution
  // The points' squared residuals (distance / point_sigma_m)^2, each at most
  // (inlier_distance_m / point_sigma_m)^2 (the log-likelihood of an inlier or a uniform outlier,
  // up to a constant), summed counting each cell's points once (see `covariance`): in chi^2
  // units, so that two poses' costs differ by a chi^2 value, and no single point (a wall's
  // point that the map's scans saw free at 10 cm cells past a doorway's edge) outweighs the rest.
  double points_cost = 0.0;
  // -2 log of the evidence p(scan | prior), up to a constant, by Laplace's approximation at the
  // solution: points_cost + the prior's whitened squared residual + log det(I + S H), S the
  // prior's covariance and H the points' Gauss-Newton Hessian (counted once per cell). The last
  // term is the Occam factor: a wide prior pays for the poses it allowed and the scan ruled out.
  // Two priors on the same scan compare by it (GraphSlam's odometry test).
  double evidence_cost = 0.0;
  double rms_m = 0.0;            // RMS distance of the inliers to the map
  double inlier_fraction = 0.0;  // of all the points, those near the map
  // Of all the points, those where the map has seen (Matchable) but not near it: they contradict
  // the pose (a point where the map has not seen says nothing, for or against).
  double misfit_fraction = 0.0;
  int iterations = 0;
  bool converged = false;
  bool accepted = false;  // passed the quality test
  std::string reason;     // why not, when not accepted
};

// Whether a point `placed` in the grid's frame (with its normal, or zero) gets a residual: the
// grid has seen where it falls; it lies along its nearest outline piece, or past its end where
// the grid saw free space (options.skip_past_outline_ends); when both have normals, the point's
// agrees with the piece's within options.max_normal_angle_rad.
bool Matchable(const DistanceGrid& grid, const OrientedPoint& placed,
               const RegistrationOptions& options);
// Whether `query` (robot frame) tells `best` from `rival` on `target`. Evidence is what fits
// one pose and not the other (Matchable, within options.inlier_distance_m); points that fit
// both, or neither, say nothing (in a corridor most of them). Neighbouring points of one outline
// move together, so the unit of evidence is a cell of `cell_m` holding such points, not a
// point: `best` is told apart when so many more cells favour it that as many would come up by
// chance, each cell going either way with probability 1/2, with probability below alpha (a
// one-sided sign test).
bool TellsApart(const DistanceGrid& target, const std::vector<OrientedPoint>& query,
                const kernel::Pose2& best, const kernel::Pose2& rival,
                const RegistrationOptions& options, double cell_m, double alpha);
// `points` (robot frame) placed at `pose`.
std::vector<OrientedPoint> Placed(const kernel::Pose2& pose,
                                  const std::vector<OrientedPoint>& points);

// Registers `points` (robot frame; those Matchable at the prior) against `grid` (world frame)
// from `prior`, whose covariance (in the prior's frame) is `prior_covariance`, or
// diag(prior_sigma_m^2, prior_sigma_m^2, prior_sigma_rad^2) when null. The second form: points
// without normals.
RegistrationResult RegisterPoints(const std::vector<OrientedPoint>& points,
                                  const DistanceGrid& grid, const kernel::Pose2& prior,
                                  const RegistrationOptions& options,
                                  const Eigen::Matrix3d* prior_covariance = nullptr);
RegistrationResult RegisterPoints(const std::vector<Eigen::Vector2d>& points,
                                  const DistanceGrid& grid, const kernel::Pose2& prior,
                                  const RegistrationOptions& options,
                                  const Eigen::Matrix3d* prior_covariance = nullptr);

// Whether an odometry increment, the prior of `fused`, is more probably right than an outlier
// known only to the wide prior of `alone` (the same scan registered from the same prediction),
// when an outlier has prior probability `outlier_probability`: the evidences differ by at most
// 2 ln((1 - p) / p). A direction the scan leaves loose costs the wide prior its Occam factor,
// and the odometry holds it; a slip moves the scan's well-defined optimum by more than the
// odometry's covariance allows.
bool OdometryIsInlier(const RegistrationResult& fused, const RegistrationResult& alone,
                      double outlier_probability);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_SCAN_REGISTRATION_H_
