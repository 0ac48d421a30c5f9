#include "estimation/topological/topological_correction.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

namespace splam::estimation {
namespace {

// wrap(phi_ref - (theta + e + phi_robot)), wrapped through atan2 so that it is smooth in e.
struct ChordAngleResidual {
  double phi_ref, theta_plus_phi_robot;
  template <class T>
  bool operator()(const T* e, T* residual) const {
    const T d = T(phi_ref) - (T(theta_plus_phi_robot) + e[0]);
    residual[0] = ceres::atan2(ceres::sin(d), ceres::cos(d));
    return true;
  }
};

// X_ref - (t + e + R(theta) p): the world point where the robot sees p is moved by e.
struct PointResidual {
  Eigen::Vector2d difference;  // X_ref - (t + R(theta) p)
  template <class T>
  bool operator()(const T* e, T* residual) const {
    residual[0] = T(difference.x()) - e[0];
    residual[1] = T(difference.y()) - e[1];
    return true;
  }
};

// R(theta) p + t - X at pose = (x, y, theta): where the robot sees p (robot frame) in the
// world, minus where the map has it.
template <class T>
void SeenMinusMap(const T* pose, const Eigen::Vector2d& p, const Eigen::Vector2d& x, T* d) {
  const T c = ceres::cos(pose[2]), s = ceres::sin(pose[2]);
  d[0] = c * p.x() - s * p.y() + pose[0] - x.x();
  d[1] = s * p.x() + c * p.y() + pose[1] - x.y();
}

// n . (R(theta) p + t - X): the signed distance of the seen point to the map curve's tangent.
struct PointToCurveResidual {
  CurvePointPair pair;
  template <class T>
  bool operator()(const T* pose, T* residual) const {
    T d[2];
    SeenMinusMap(pose, pair.robot_point, pair.map_point, d);
    residual[0] = pair.map_normal.x() * d[0] + pair.map_normal.y() * d[1];
    return true;
  }
};

// R(theta) p + t - X: a paired feature, a physical point.
struct FeatureResidual {
  PointPair pair;
  template <class T>
  bool operator()(const T* pose, T* residual) const {
    SeenMinusMap(pose, pair.robot_point, pair.map_point, residual);
    return true;
  }
};

void SolveQuietly(ceres::Problem* problem, SolverCounts* counts) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 20;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  if (counts != nullptr) {
    ++counts->runs;
    counts->failures += summary.termination_type != ceres::CONVERGENCE;
  }
}

// The weight multiplies the robust loss of the unweighted residual, so that the Huber scale
// stays in radians or metres.
ceres::LossFunction* WeightedHuber(double scale, double weight) {
  return new ceres::ScaledLoss(new ceres::HuberLoss(scale), weight, ceres::TAKE_OWNERSHIP);
}

}  // namespace

double SolveHeadingCorrection(const std::vector<ChordPair>& chords, double theta_rad,
                              const CorrectionLossOptions& loss, SolverCounts* counts) {
  double e = 0.0;
  if (chords.empty()) return e;
  ceres::Problem problem;
  for (const ChordPair& c : chords) {
    const double phi_ref = std::atan2(c.map_direction.y(), c.map_direction.x());
    const double phi_robot = std::atan2(c.robot_direction.y(), c.robot_direction.x());
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ChordAngleResidual, 1, 1>(
                                 new ChordAngleResidual{phi_ref, theta_rad + phi_robot}),
                             WeightedHuber(loss.heading_scale_rad, c.weight), &e);
  }
  SolveQuietly(&problem, counts);
  return e;
}

Eigen::Vector2d SolveTranslationCorrection(const std::vector<PointPair>& points,
                                           const Eigen::Vector2d& translation, double theta_rad,
                                           const CorrectionLossOptions& loss,
                                           SolverCounts* counts) {
  double e[2] = {0.0, 0.0};
  if (points.empty()) return Eigen::Vector2d::Zero();
  const Eigen::Rotation2Dd rotation(theta_rad);
  ceres::Problem problem;
  for (const PointPair& p : points) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointResidual, 2, 2>(new PointResidual{
                                 p.map_point - (translation + rotation * p.robot_point)}),
                             WeightedHuber(loss.translation_scale_m, p.weight), e);
  }
  SolveQuietly(&problem, counts);
  return {e[0], e[1]};
}

kernel::Pose2 SolvePoseCorrection(const std::vector<CurvePointPair>& on_curves,
                                  const std::vector<PointPair>& features, const kernel::Pose2& pose,
                                  double min_information, const CorrectionLossOptions& loss,
                                  SolverCounts* counts) {
  if (on_curves.empty() && features.empty()) return pose;
  double x[3] = {pose.x(), pose.y(), pose.theta()};
  ceres::Problem problem;
  for (const CurvePointPair& p : on_curves) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PointToCurveResidual, 1, 3>(new PointToCurveResidual{p}),
        WeightedHuber(loss.translation_scale_m, p.weight), x);
  }
  for (const PointPair& p : features) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<FeatureResidual, 2, 3>(new FeatureResidual{p}),
        WeightedHuber(loss.translation_scale_m, p.weight), x);
  }
  SolveQuietly(&problem, counts);
  // The step, kept only in the directions the points constrain.
  const Eigen::Vector3d step(x[0] - pose.x(), x[1] - pose.y(),
                             std::remainder(x[2] - pose.theta(), 2.0 * M_PI));
  const Eigen::Vector3d kept =
      PointInformation(on_curves, features, pose.theta(), min_information).Projector() * step;
  return kernel::Pose2(pose.x() + kept.x(), pose.y() + kept.y(), pose.theta() + kept.z());
}

PoseInformation PointInformation(const std::vector<CurvePointPair>& on_curves,
                                 const std::vector<PointPair>& features, double theta_rad,
                                 double min_information) {
  // Rows n^T [I, R' p] for the curve points, [I, R' p] for the features (R' = dR / dtheta).
  const Eigen::Rotation2Dd turned(theta_rad + 0.5 * M_PI);  // R' p = R(theta + pi/2) p
  Eigen::Matrix3d counted = Eigen::Matrix3d::Zero(), weighted = Eigen::Matrix3d::Zero();
  auto add = [&](const Eigen::Vector2d& row_xy, const Eigen::Vector2d& robot_point, double weight) {
    const Eigen::Vector3d j(row_xy.x(), row_xy.y(), row_xy.dot(turned * robot_point));
    counted += j * j.transpose();
    weighted += weight * j * j.transpose();
  };
  for (const CurvePointPair& p : on_curves) add(p.map_normal, p.robot_point, p.weight);
  for (const PointPair& p : features) {
    add(Eigen::Vector2d::UnitX(), p.robot_point, p.weight);
    add(Eigen::Vector2d::UnitY(), p.robot_point, p.weight);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(counted);
  PoseInformation out;
  out.weighted = weighted;
  for (int i = 0; i < 3; ++i) {
    if (eigen.eigenvalues()(i) < min_information) continue;
    out.directions.conservativeResize(Eigen::NoChange, out.directions.cols() + 1);
    out.directions.rightCols<1>() = eigen.eigenvectors().col(i);
  }
  return out;
}

void CorrectionLossOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("heading_scale_rad", &heading_scale_rad, "Huber scale of the chord residuals, rad");
  v.Field("translation_scale_m", &translation_scale_m, "Huber scale of the point residuals, m");
}

}  // namespace splam::estimation
