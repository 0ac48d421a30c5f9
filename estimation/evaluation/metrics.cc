#include "estimation/evaluation/metrics.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::evaluation {
std::pair<double, double> MeanStd(const std::vector<double>& v) {
  if (v.empty()) return {0.0, 0.0};
  double sum = 0.0, sum2 = 0.0;
  for (double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  for (double x : v) sum2 += (x - mean) * (x - mean);
  return {mean, std::sqrt(sum2 / static_cast<double>(v.size()))};
}

TrajectoryError CompareToTruth(const kernel::Trajectory& unsorted_truth,
                               const kernel::Trajectory& estimate) {
  const kernel::Trajectory truth = kernel::SortedByTime(unsorted_truth);
  TrajectoryError e;
  double sum_p2 = 0.0, sum_h2 = 0.0;
  for (const kernel::StampedPose& est : estimate) {
    const std::optional<kernel::Pose2> t = kernel::PoseAt(truth, est.time_s);
    if (!t) continue;
    const double ex = est.pose.x() - t->x(), ey = est.pose.y() - t->y();
    const double eth = kernel::WrapAngle(est.pose.theta() - t->theta());
    e.time_s.push_back(est.time_s);
    e.error_x_m.push_back(ex);
    e.error_y_m.push_back(ey);
    e.error_theta_rad.push_back(eth);
    const double p2 = ex * ex + ey * ey;
    sum_p2 += p2;
    sum_h2 += eth * eth;
    e.max_position_m = std::max(e.max_position_m, std::sqrt(p2));
    e.max_heading_rad = std::max(e.max_heading_rad, std::abs(eth));
  }
  e.matched = e.time_s.size();
  if (e.matched > 0) {
    e.rmse_position_m = std::sqrt(sum_p2 / static_cast<double>(e.matched));
    e.rmse_heading_rad = std::sqrt(sum_h2 / static_cast<double>(e.matched));
  }
  return e;
}

RelationsError EvaluateRelations(const std::vector<Relation>& relations,
                                 const kernel::Trajectory& unsorted_estimate) {
  const kernel::Trajectory estimate = kernel::SortedByTime(unsorted_estimate);
  RelationsError r;
  std::vector<double> trans, trans2, rot, rot2;
  for (const Relation& rel : relations) {
    // Relation times are scan timestamps: match them to 1 ms, else interpolate over < 1 s.
    const std::optional<kernel::Pose2> a = kernel::PoseAt(estimate, rel.t1, 1.0, 1e-3);
    const std::optional<kernel::Pose2> b = kernel::PoseAt(estimate, rel.t2, 1.0, 1e-3);
    if (!a || !b) {
      ++r.skipped;
      continue;
    }
    const kernel::Pose2 est = a->Between(*b);
    const double t = (rel.motion.translation() - est.translation()).norm();
    const double q = std::abs(kernel::WrapAngle(rel.motion.theta() - est.theta()));
    trans.push_back(t);
    trans2.push_back(t * t);
    rot.push_back(q);
    rot2.push_back(q * q);
  }
  r.used = trans.size();
  std::tie(r.translation_mean, r.translation_std) = MeanStd(trans);
  std::tie(r.translation_sq_mean, r.translation_sq_std) = MeanStd(trans2);
  std::tie(r.rotation_mean, r.rotation_std) = MeanStd(rot);
  std::tie(r.rotation_sq_mean, r.rotation_sq_std) = MeanStd(rot2);
  return r;
}

double PoseNees(const kernel::Pose2& truth, const kernel::Pose2& estimate,
                const Eigen::Matrix3d& covariance) {
  const Eigen::Vector3d e(estimate.x() - truth.x(), estimate.y() - truth.y(),
                          kernel::WrapAngle(estimate.theta() - truth.theta()));
  return e.dot(covariance.ldlt().solve(e));
}

}  // namespace splam::evaluation
