#include "estimation/models.h"

#include <cmath>

#include "kernel/angle.h"

namespace splam::estimation {

using kernel::kPi;
using kernel::WrapAngle;

kernel::Pose2 MotionModel(const kernel::Pose2& x, const kernel::Pose2& u,
                          MotionJacobians* jacobians) {
  const double c = std::cos(x.theta()), s = std::sin(x.theta());
  if (jacobians != nullptr) {
    jacobians->f_x << 1, 0, -u.x() * s - u.y() * c, 0, 1, u.x() * c - u.y() * s, 0, 0, 1;
    jacobians->f_u << c, -s, 0, s, c, 0, 0, 0, 1;
  }
  return kernel::Pose2(x.x() + u.x() * c - u.y() * s, x.y() + u.x() * s + u.y() * c,
                       x.theta() + u.theta());
}

Eigen::Matrix3d OdometryNoiseModel::Covariance(const kernel::Pose2& u) const {
  const double d = u.translation().norm();
  const double sx = forward_per_m * d + translation_floor_m;
  const double sy = lateral_per_m * d + translation_floor_m;
  const double sth =
      rotation_per_rad * std::abs(u.theta()) + rotation_per_m * d + rotation_floor_rad;
  return Eigen::Vector3d(sx * sx, sy * sy, sth * sth).asDiagonal();
}

kernel::Status OdometryNoiseModel::Validate() const {
  // Bounded above too: a variance of (1e200)^2 overflows to infinity, and the filters' and
  // solvers' weights with it (a sigma of 10 per metre already says "no odometry").
  for (const double c : {forward_per_m, lateral_per_m, rotation_per_rad, rotation_per_m})
    if (!(c >= 0 && c <= 10))
      return kernel::Status::Error("odometry noise coefficients must be in [0, 10]");
  for (const double floor : {translation_floor_m, rotation_floor_rad})
    if (!(floor > 0 && floor <= 10))
      return kernel::Status::Error("odometry noise floors must be in (0, 10]");
  return kernel::Status::Ok();
}

Line TransformLine(const kernel::Pose2& a_T_b, const Line& line_b) {
  // Points p_b on the line satisfy n_b . p_b = rho_b; with p_a = R p_b + t, n_a = R n_b and
  // rho_a = rho_b + n_a . t.
  Line out{line_b.rho, WrapAngle(line_b.theta + a_T_b.theta())};
  out.rho += std::cos(out.theta) * a_T_b.x() + std::sin(out.theta) * a_T_b.y();
  if (out.rho < 0.0) {
    out.rho = -out.rho;
    out.theta = WrapAngle(out.theta + kPi);
  }
  return out;
}

Eigen::Vector2d PredictLine(const kernel::Pose2& x, const Line& l, Matrix23* h_r,
                            Eigen::Matrix2d* h_l) {
  const double c = std::cos(l.theta), s = std::sin(l.theta);
  double rho = l.rho - x.x() * c - x.y() * s;
  double theta = l.theta - x.theta();
  Matrix23 hr;
  Eigen::Matrix2d hl;
  hr << -c, -s, 0, 0, 0, -1;
  hl << 1, x.x() * s - x.y() * c, 0, 1;
  if (rho < 0.0) {
    rho = -rho;
    theta += kPi;
    hr.row(0) *= -1.0;
    hl.row(0) *= -1.0;
  }
  if (h_r != nullptr) *h_r = hr;
  if (h_l != nullptr) *h_l = hl;
  return {rho, WrapAngle(theta)};
}

Eigen::Vector2d LineInnovation(const Eigen::Vector2d& z, const Eigen::Vector2d& h, Matrix23* h_r,
                               Eigen::Matrix2d* h_l) {
  const double angle = WrapAngle(z(1) - h(1));
  if (std::abs(angle) <= kPi / 2) return {z(0) - h(0), angle};
  if (h_r != nullptr) h_r->row(0) *= -1.0;
  if (h_l != nullptr) h_l->row(0) *= -1.0;
  return {z(0) + h(0), WrapAngle(angle - kPi)};
}

Line InitializeLine(const kernel::Pose2& x, const Line& z, Matrix23* g_r, Eigen::Matrix2d* g_z) {
  const double a = x.theta() + z.theta;
  const double c = std::cos(a), s = std::sin(a);
  double rho = z.rho + x.x() * c + x.y() * s;
  double theta = a;
  Matrix23 gr;
  Eigen::Matrix2d gz;
  gr << c, s, -x.x() * s + x.y() * c, 0, 0, 1;
  gz << 1, -x.x() * s + x.y() * c, 0, 1;
  if (rho < 0.0) {
    rho = -rho;
    theta += kPi;
    gr.row(0) *= -1.0;
    gz.row(0) *= -1.0;
  }
  if (g_r != nullptr) *g_r = gr;
  if (g_z != nullptr) *g_z = gz;
  return {rho, WrapAngle(theta)};
}

Eigen::Vector2d PredictPoint(const kernel::Pose2& x, const Eigen::Vector2d& p, Matrix23* h_r,
                             Eigen::Matrix2d* h_c) {
  const double c = std::cos(x.theta()), s = std::sin(x.theta());
  const Eigen::Vector2d d = p - x.translation();
  if (h_r != nullptr) *h_r << -c, -s, -s * d.x() + c * d.y(), s, -c, -c * d.x() - s * d.y();
  if (h_c != nullptr) *h_c << c, s, -s, c;
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

Eigen::Vector2d InitializePoint(const kernel::Pose2& x, const Eigen::Vector2d& z, Matrix23* g_r,
                                Eigen::Matrix2d* g_z) {
  const double c = std::cos(x.theta()), s = std::sin(x.theta());
  if (g_r != nullptr) *g_r << 1, 0, -s * z.x() - c * z.y(), 0, 1, c * z.x() - s * z.y();
  if (g_z != nullptr) *g_z << c, -s, s, c;
  return x.translation() + Eigen::Vector2d(c * z.x() - s * z.y(), s * z.x() + c * z.y());
}

void OdometryNoiseModel::VisitFields(kernel::FieldVisitor& v) {
  v.Field("forward_per_m", &forward_per_m, "forward sigma per m travelled");
  v.Field("lateral_per_m", &lateral_per_m, "sideways sigma per m travelled");
  v.Field("rotation_per_rad", &rotation_per_rad, "heading sigma per rad turned");
  v.Field("rotation_per_m", &rotation_per_m, "heading sigma per m travelled, rad/m");
  v.Field("translation_floor_m", &translation_floor_m, "translation sigma floor per step, m");
  v.Field("rotation_floor_rad", &rotation_floor_rad, "rotation sigma floor per step, rad");
}

}  // namespace splam::estimation
