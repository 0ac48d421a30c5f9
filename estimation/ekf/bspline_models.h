#ifndef SPLAM_ESTIMATION_EKF_BSPLINE_MODELS_H_
#define SPLAM_ESTIMATION_EKF_BSPLINE_MODELS_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "kernel/bspline.h"
#include "kernel/pose2.h"

// The observation model of EKF-SLAM with B-splines (SPEC §8, Pedraza et al. 2009): the expected
// range of a laser beam is where the beam meets the map curve.
namespace splam::estimation {

struct BeamPrediction {
  double range_m = 0.0;          // r*: distance from the laser to the curve along the beam
  double curve_parameter = 0.0;  // u*: where the beam meets the curve
  // Jacobians of r* with respect to the robot pose (x, y, th) and to the four control points that
  // shape the curve at u*: (X_first.x, X_first.y, ..., X_first+3.x, X_first+3.y).
  Eigen::RowVector3d d_range_d_pose = Eigen::RowVector3d::Zero();
  std::size_t first_control = 0;
  Eigen::Matrix<double, 1, 8> d_range_d_controls = Eigen::Matrix<double, 1, 8>::Zero();
};

// The beam at angle beam_angle_rad (laser frame) of a laser mounted at robot_T_laser on a robot
// at world_T_robot, against a world-frame curve. With o the beam's origin, d its direction and
// C(u) = sum_i X_i N_i(u), the hit solves F(r, u) = o + r d - C(u) = 0. By the implicit function
// theorem, with A = [d, -C'(u*)] (2x2):
//   d(r, u)/dp = -A^-1 dF/dp,  dF/d(x, y) = I,  dF/dth = R'(th) l + r* d_perp,
//   d(r, u)/dX_i = A^-1 N_i(u*),
// l the laser's position on the robot and d_perp = (-sin, cos) of the beam's world angle.
// nullopt when the beam misses the curve within max_range_m, or meets it at a grazing angle
// (sine of the angle between beam and tangent below min_incidence_sine), where the range is
// ill-conditioned.
std::optional<BeamPrediction> PredictBeam(const kernel::Pose2& world_T_robot,
                                          const kernel::Pose2& robot_T_laser, double beam_angle_rad,
                                          const kernel::CubicBSpline& curve, double max_range_m,
                                          double min_incidence_sine = 0.1);

// Measured points in the world frame, D_k = t + R(th) l_T (r_k cos a_k, r_k sin a_k) for a laser
// at robot_T_laser = l_T on a robot at (t, th), with dD_k/d(x, y, th) and dD_k/dr_k (the beam's
// world direction).
struct BeamPoints {
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Matrix<double, 2, 3>> d_pose;
  std::vector<Eigen::Vector2d> d_range;
};
BeamPoints BeamPointsInWorld(const kernel::Pose2& world_T_robot, const kernel::Pose2& robot_T_laser,
                             const std::vector<double>& ranges, const std::vector<double>& angles);

// New control points from measured points (SPEC §8: g(X_r, Z) for augmentation and extension).
// A least-squares fit is linear in the data, X_i = sum_k M(i, k) D_k (kernel::
// CubicBSplineFitOperator); the beams' points are the data columns `columns` of M. Adds their part
// of the interleaved control vector (x_0, y_0, x_1, ...) to *controls and of its Jacobian by the
// pose to *d_pose (2n x 3), and returns the Jacobian by the ranges (2n x beams). M itself depends
// on the points only through their chord-length parameters, which are invariant under rigid
// motion: d_pose is exact, the range Jacobian holds M fixed (as Pedraza et al. do).
Eigen::MatrixXd AddBeamColumns(const Eigen::MatrixXd& m, const std::vector<Eigen::Index>& columns,
                               const BeamPoints& beams, Eigen::VectorXd* controls,
                               Eigen::MatrixXd* d_pose);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_BSPLINE_MODELS_H_
