#include "estimation/ekf/bspline_models.h"

#include <Eigen/LU>
#include <cmath>

namespace splam::estimation {

std::optional<BeamPrediction> PredictBeam(const kernel::Pose2& world_T_robot,
                                          const kernel::Pose2& robot_T_laser, double beam_angle_rad,
                                          const kernel::CubicBSpline& curve, double max_range_m,
                                          double min_incidence_sine) {
  const kernel::Pose2 world_T_laser = world_T_robot * robot_T_laser;
  const double angle = world_T_laser.theta() + beam_angle_rad;
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  const kernel::Ray2 ray{world_T_laser.translation(), d};
  const double r = kernel::Intersect(ray, curve, 0.0, max_range_m);
  if (r == kernel::kNoHit) return std::nullopt;
  const double u = curve.Closest(ray.At(r)).t;
  const Eigen::Vector2d tangent = curve.Derivative(u);
  const double cross = d.x() * tangent.y() - d.y() * tangent.x();
  if (std::abs(cross) < min_incidence_sine * tangent.norm()) return std::nullopt;

  Eigen::Matrix2d a;
  a.col(0) = d;
  a.col(1) = -tangent;
  const Eigen::Matrix2d a_inv = a.inverse();
  // dF/dth: the origin swings around the robot and the beam turns.
  const double c = std::cos(world_T_robot.theta()), s = std::sin(world_T_robot.theta());
  const Eigen::Vector2d& l = robot_T_laser.translation();
  const Eigen::Vector2d d_origin_d_th(-s * l.x() - c * l.y(), c * l.x() - s * l.y());
  Eigen::Matrix<double, 2, 3> d_f_d_pose;
  d_f_d_pose.leftCols<2>().setIdentity();
  d_f_d_pose.col(2) = d_origin_d_th + r * Eigen::Vector2d(-d.y(), d.x());

  BeamPrediction p;
  p.range_m = r;
  p.curve_parameter = u;
  p.d_range_d_pose = -(a_inv * d_f_d_pose).row(0);
  const kernel::CubicBSpline::Basis basis = curve.BasisAt(u);
  p.first_control = basis.first;
  for (int k = 0; k < 4; ++k)
    p.d_range_d_controls.segment<2>(2 * k) = basis.values[k] * a_inv.row(0);
  return p;
}

BeamPoints BeamPointsInWorld(const kernel::Pose2& world_T_robot, const kernel::Pose2& robot_T_laser,
                             const std::vector<double>& ranges, const std::vector<double>& angles) {
  BeamPoints b;
  const Eigen::Matrix2d rotation = world_T_robot.Rotation();
  const Eigen::Matrix2d d_rotation{{-rotation(1, 0), -rotation(0, 0)},
                                   {rotation(0, 0), -rotation(1, 0)}};  // dR/dth
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const Eigen::Vector2d direction(std::cos(angles[k]), std::sin(angles[k]));
    const Eigen::Vector2d in_robot = robot_T_laser * (ranges[k] * direction);
    b.points.push_back(world_T_robot * in_robot);
    Eigen::Matrix<double, 2, 3> d;
    d.leftCols<2>().setIdentity();
    d.col(2) = d_rotation * in_robot;
    b.d_pose.push_back(d);
    b.d_range.push_back(rotation * robot_T_laser.Rotation() * direction);
  }
  return b;
}

Eigen::MatrixXd AddBeamColumns(const Eigen::MatrixXd& m, const std::vector<Eigen::Index>& columns,
                               const BeamPoints& beams, Eigen::VectorXd* controls,
                               Eigen::MatrixXd* d_pose) {
  const Eigen::Index n = m.rows();
  Eigen::MatrixXd d_ranges =
      Eigen::MatrixXd::Zero(2 * n, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const auto col = m.col(columns[k]);
    for (Eigen::Index i = 0; i < n; ++i) {
      controls->segment<2>(2 * i) += col(i) * beams.points[k];
      d_pose->middleRows<2>(2 * i) += col(i) * beams.d_pose[k];
      d_ranges.col(static_cast<Eigen::Index>(k)).segment<2>(2 * i) = col(i) * beams.d_range[k];
    }
  }
  return d_ranges;
}

}  // namespace splam::estimation
