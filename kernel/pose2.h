#ifndef SPLAM_KERNEL_POSE2_H_
#define SPLAM_KERNEL_POSE2_H_

#include <Eigen/Core>
#include <vector>

namespace splam::kernel {

// Beyond this a coordinate is not a robot's or a building's (1000 km): the readers and the world
// check refuse it; a map at 1e238 had overflowed a DXF export's number formatting, m.
inline constexpr double kMaxCoordinateM = 1e6;

// A rigid transformation of the plane, a_T_b: maps coordinates in frame b to frame a.
// As a robot pose it is world_T_robot = (x, y, theta): the robot's origin in the world and its
// heading, theta wrapped to (-pi, pi].
class Pose2 {
 public:
  Pose2() = default;
  Pose2(double x, double y, double theta_rad);
  Pose2(const Eigen::Vector2d& translation, double theta_rad);

  double x() const { return translation_.x(); }
  double y() const { return translation_.y(); }
  double theta() const { return theta_rad_; }
  const Eigen::Vector2d& translation() const { return translation_; }
  Eigen::Matrix2d Rotation() const;
  Eigen::Vector3d ToVector() const { return {x(), y(), theta_rad_}; }

  // a_T_c = a_T_b * b_T_c.
  Pose2 operator*(const Pose2& b_T_c) const;
  // p_a = a_T_b * p_b.
  Eigen::Vector2d operator*(const Eigen::Vector2d& p_b) const;
  std::vector<Eigen::Vector2d> operator*(const std::vector<Eigen::Vector2d>& points_b) const;
  // b_T_a.
  Pose2 Inverse() const;
  // The motion from this pose to `other`, expressed in this pose's frame: Inverse() * other.
  // Odometry increments and relations are of this form.
  Pose2 Between(const Pose2& other) const { return Inverse() * other; }

 private:
  Eigen::Vector2d translation_ = Eigen::Vector2d::Zero();
  double theta_rad_ = 0.0;
};

// Largest |difference| over x, y and the wrapped angle difference.
// The exact motion in the robot frame of a unicycle driven at constant (v, w) for dt: an arc of
// radius v / w, or a straight line when w == 0.
Pose2 UnicycleIncrement(double v_mps, double w_radps, double dt_s);

double MaxAbsDifference(const Pose2& a, const Pose2& b);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_POSE2_H_
