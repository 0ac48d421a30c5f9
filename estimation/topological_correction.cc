#include "estimation/topological_correction.h"

#include <ceres/ceres.h>

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

void SolveQuietly(ceres::Problem* problem, SolverCounts* counts) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
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

void CorrectionLossOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("heading_scale_rad", &heading_scale_rad, "Huber scale of the chord residuals, rad");
  v.Field("translation_scale_m", &translation_scale_m, "Huber scale of the point residuals, m");
}

}  // namespace splam::estimation
