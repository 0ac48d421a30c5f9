#include "kernel/pose2.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {

Pose2::Pose2(double x, double y, double theta_rad)
    : translation_(x, y), theta_rad_(WrapAngle(theta_rad)) {}

Pose2::Pose2(const Eigen::Vector2d& translation, double theta_rad)
    : translation_(translation), theta_rad_(WrapAngle(theta_rad)) {}

Eigen::Matrix2d Pose2::Rotation() const {
  const double c = std::cos(theta_rad_);
  const double s = std::sin(theta_rad_);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

Pose2 Pose2::operator*(const Pose2& b_T_c) const {
  return Pose2(translation_ + Rotation() * b_T_c.translation_, theta_rad_ + b_T_c.theta_rad_);
}

Eigen::Vector2d Pose2::operator*(const Eigen::Vector2d& p_b) const {
  return translation_ + Rotation() * p_b;
}

std::vector<Eigen::Vector2d> Pose2::operator*(const std::vector<Eigen::Vector2d>& points_b) const {
  const Eigen::Matrix2d r = Rotation();
  std::vector<Eigen::Vector2d> points_a;
  points_a.reserve(points_b.size());
  for (const Eigen::Vector2d& p : points_b) points_a.push_back(translation_ + r * p);
  return points_a;
}

Pose2 Pose2::Inverse() const {
  return Pose2(-(Rotation().transpose() * translation_), -theta_rad_);
}

double MaxAbsDifference(const Pose2& a, const Pose2& b) {
  return std::max({std::abs(a.x() - b.x()), std::abs(a.y() - b.y()),
                   std::abs(WrapAngle(a.theta() - b.theta()))});
}

Pose2 UnicycleIncrement(double v_mps, double w_radps, double dt_s) {
  const double dth = w_radps * dt_s;
  if (std::abs(dth) < 1e-12) return Pose2(v_mps * dt_s, 0.0, dth);
  const double r = v_mps / w_radps;
  return Pose2(r * std::sin(dth), r * (1.0 - std::cos(dth)), dth);
}

}  // namespace splam::kernel
