#ifndef SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_CORRECTION_H_
#define SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_CORRECTION_H_

#include <Eigen/Core>
#include <vector>

#include "kernel/options.h"
#include "kernel/pose2.h"

// The two weighted least-squares problems of the topological localisation (SPEC §10, paper 003
// eqs. 6-10), solved with Ceres. Everything Ceres is confined to this header's source file.
namespace splam::estimation {

// One associated chord: the map's chord (world frame) and the observed chord (robot frame)
// between the start and end points of a matched stretch, with its reliability weight C_i.
struct ChordPair {
  Eigen::Vector2d map_direction = Eigen::Vector2d::UnitX();    // X_ref,F - X_ref,I
  Eigen::Vector2d robot_direction = Eigen::Vector2d::UnitX();  // p_F - p_I in the robot frame
  double weight = 1.0;
};

// One associated point: where the map has it (world) and where the robot sees it (robot frame).
struct PointPair {
  Eigen::Vector2d map_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d robot_point = Eigen::Vector2d::Zero();
  double weight = 1.0;
};

// One point of an associated stretch: where the robot sees it (robot frame), and the map curve
// linearised at the point's projection (world frame): the closest point X and the unit normal n.
struct CurvePointPair {
  Eigen::Vector2d robot_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d map_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d map_normal = Eigen::Vector2d::UnitY();
  double weight = 1.0;
};

struct CorrectionLossOptions {
  // Residuals beyond these scales are down-weighted (Huber): one wrong chord or point cannot
  // drag the solution far. Radians and metres.
  double heading_scale_rad = 0.05;
  double translation_scale_m = 0.1;
  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
};

// Least-squares solves (Ceres) and those whose summary did not report convergence; the solvers
// below add to it when given one.
struct SolverCounts {
  int runs = 0;
  int failures = 0;
  SolverCounts& operator+=(const SolverCounts& o) {
    runs += o.runs;
    failures += o.failures;
    return *this;
  }
};

// Angular correction (eq. 8): e_theta = argmin sum_i C_i wrap(phi_ref_i - phi_curr_i(e))^2, where
// phi_ref is the direction of the map chord and phi_curr(e) = theta + e + direction of the
// observed chord in the robot frame. The residual is on the wrapped chord direction angle, the
// bounded form of the paper's slope difference (a slope is infinite for vertical chords).
// Returns e_theta (0 without chords).
double SolveHeadingCorrection(const std::vector<ChordPair>& chords, double theta_rad,
                              const CorrectionLossOptions& loss = {},
                              SolverCounts* counts = nullptr);

// Translational correction (eqs. 9-10) with the heading already corrected: (e_x, e_y) =
// argmin sum_i C_i |X_ref_i - (t + e + R(theta) p_i)|^2. Returns (e_x, e_y) (zero without points).
Eigen::Vector2d SolveTranslationCorrection(const std::vector<PointPair>& points,
                                           const Eigen::Vector2d& translation, double theta_rad,
                                           const CorrectionLossOptions& loss = {},
                                           SolverCounts* counts = nullptr);

// What a set of point pairs says about the pose (x, y, theta), linearised at heading theta_rad:
// the residuals' Jacobians J_i = d r_i / d(x, y, theta) (theta in radians, so a direction mixes
// metres and radians as if the points were 1 m away). `directions` are the orthonormal
// eigenvectors of the unweighted information sum_i J_i^T J_i whose eigenvalue is at least
// min_information (in units of points whose normal lies along that direction; a feature counts
// 2): the directions the points constrain, one per column. `weighted` is sum_i C_i J_i^T J_i.
struct PoseInformation {
  Eigen::Matrix3d weighted = Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 3, Eigen::Dynamic> directions = Eigen::Matrix<double, 3, 0>();
  // Projects (x, y, theta) onto the constrained directions.
  Eigen::Matrix3d Projector() const { return directions * directions.transpose(); }
};
PoseInformation PointInformation(const std::vector<CurvePointPair>& on_curves,
                                 const std::vector<PointPair>& features, double theta_rad,
                                 double min_information);

// Joint correction of heading and position from point-to-curve distances (the default in
// place of eqs. 7-10): the pose (x, y, theta) = argmin sum_i C_i rho(n_i . (R(theta) p_i + t -
// X_i)) + sum_j C_j rho(|R(theta) p_j + t - X_j|) over the curve points i and the paired
// features j, started at `pose`. A point may slide along its curve at no cost, so a position
// error along a smooth curve is not read as a heading error (as a chord projected onto the map
// is). Where the curves leave a direction of (x, y, theta) unconstrained (along one straight
// wall, about the centre of one circle), the solution would slide along it with the noise of the
// fitted curves' normals: the step from `pose` is kept only in the directions the points
// constrain (PointInformation's directions at `pose`). Returns `pose` without points.
kernel::Pose2 SolvePoseCorrection(const std::vector<CurvePointPair>& on_curves,
                                  const std::vector<PointPair>& features, const kernel::Pose2& pose,
                                  double min_information, const CorrectionLossOptions& loss = {},
                                  SolverCounts* counts = nullptr);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_CORRECTION_H_
