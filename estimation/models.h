#ifndef SPLAM_ESTIMATION_MODELS_H_
#define SPLAM_ESTIMATION_MODELS_H_

#include <Eigen/Core>
#include <string>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

// The motion and observation models of EKF-SLAM with lines and corners (SPEC §2, §4), as pure
// functions with their Jacobians; tests check every Jacobian against numeric differentiation.
namespace splam::estimation {

using Matrix23 = Eigen::Matrix<double, 2, 3>;

// --- Motion (SPEC §2) ---------------------------------------------------------------------
// x' = x (+) u for a pose x = (x, y, th) and an odometry increment u = (dx, dy, dth) in the
// robot frame; F_x = dx'/dx, F_u = dx'/du.
struct MotionJacobians {
  Eigen::Matrix3d f_x;
  Eigen::Matrix3d f_u;
};
kernel::Pose2 MotionModel(const kernel::Pose2& x, const kernel::Pose2& u,
                          MotionJacobians* jacobians = nullptr);

// Odometry noise (SPEC §2): U = diag(sigma_dx^2, sigma_dy^2, sigma_dth^2) with standard
// deviations proportional to the motion, the same form as the simulator's odometry model
// (sim::OdometryNoiseOptions), plus small floors that keep U positive definite.
struct OdometryNoiseModel {
  double forward_per_m = 0.03;
  double lateral_per_m = 0.01;
  double rotation_per_rad = 0.03;
  double rotation_per_m = 0.01;
  double translation_floor_m = 1e-4;  // per step
  double rotation_floor_rad = 1e-4;   // per step

  Eigen::Matrix3d Covariance(const kernel::Pose2& u) const;
  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
  // The model with its four proportional sigmas times `factor` (the floors unchanged).
  OdometryNoiseModel Scaled(double factor) const {
    OdometryNoiseModel m = *this;
    m.forward_per_m *= factor;
    m.lateral_per_m *= factor;
    m.rotation_per_rad *= factor;
    m.rotation_per_m *= factor;
    return m;
  }
};

// --- Lines (SPEC §3-4) --------------------------------------------------------------------
// A line in normal form x cos(theta) + y sin(theta) = rho.
struct Line {
  double rho = 0.0;
  double theta = 0.0;
};

// The line (rho >= 0, theta wrapped) in frame a of a line given in frame b.
Line TransformLine(const kernel::Pose2& a_T_b, const Line& line_b);

// Predicted observation of world line L = (rho, theta) from robot pose x (SPEC §4, 001 eq. 16):
//   h = [rho - x cos(theta) - y sin(theta); theta - th]
// H_r = dh/dx (2x3), H_L = dh/dL (2x2). When the predicted rho is negative the line is seen from
// its other side: h = [-h_rho; h_theta + pi], with the rho rows of H negated, consistently.
// h_theta is wrapped to (-pi, pi].
Eigen::Vector2d PredictLine(const kernel::Pose2& x, const Line& world_line, Matrix23* h_r = nullptr,
                            Eigen::Matrix2d* h_l = nullptr);

// The innovation z - h of a line z observed in normal form against its prediction h
// (PredictLine), with h taken in whichever of its two forms, (rho, theta) or (-rho, theta + pi),
// lies nearer z in angle (|theta innovation| <= pi/2); when h is turned, the rho rows of its
// Jacobians h_r, h_l (may be null) are negated with it. For a line through the sensor (rho near
// 0) the sign of either rho is set by noise: compared as they come, the two forms of one line
// differ by pi in angle, and the filter would take its own wall for a new one.
Eigen::Vector2d LineInnovation(const Eigen::Vector2d& z, const Eigen::Vector2d& h,
                               Matrix23* h_r = nullptr, Eigen::Matrix2d* h_l = nullptr);

// A new world line from a line z = (rho_o, theta_o) observed in the robot frame at pose x
// (SPEC §4, 001 eq. 29-38): g = [rho_o + x cos(th + theta_o) + y sin(th + theta_o); th + theta_o],
// normalised to rho >= 0; G_r = dg/dx, G_z = dg/dz.
Line InitializeLine(const kernel::Pose2& x, const Line& observed, Matrix23* g_r = nullptr,
                    Eigen::Matrix2d* g_z = nullptr);

// --- Corner points (SPEC §4, 003 §2.2) ----------------------------------------------------
// Predicted observation of world point c from pose x: h = R(th)^T (c - t).
Eigen::Vector2d PredictPoint(const kernel::Pose2& x, const Eigen::Vector2d& world_point,
                             Matrix23* h_r = nullptr, Eigen::Matrix2d* h_c = nullptr);
// A new world point from a point z observed in the robot frame: g = t + R(th) z.
Eigen::Vector2d InitializePoint(const kernel::Pose2& x, const Eigen::Vector2d& observed,
                                Matrix23* g_r = nullptr, Eigen::Matrix2d* g_z = nullptr);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_MODELS_H_
