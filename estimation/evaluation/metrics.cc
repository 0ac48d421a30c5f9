#include "estimation/evaluation/metrics.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <tuple>

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

kernel::Pose2 AlignPoints(const std::vector<Eigen::Vector2d>& a,
                          const std::vector<Eigen::Vector2d>& b) {
  if (a.empty() || a.size() != b.size()) return kernel::Pose2();
  Eigen::Vector2d mean_a = Eigen::Vector2d::Zero(), mean_b = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) mean_a += a[i], mean_b += b[i];
  mean_a /= static_cast<double>(a.size());
  mean_b /= static_cast<double>(b.size());
  // sum b'.(R a') = cos(phi) sum a'.b' + sin(phi) sum a' x b', largest at this phi.
  double dot = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d p = a[i] - mean_a, q = b[i] - mean_b;
    dot += p.dot(q);
    cross += p.x() * q.y() - p.y() * q.x();
  }
  const double phi = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);
  const kernel::Pose2 rotation(0.0, 0.0, phi);
  return kernel::Pose2(mean_b - rotation * mean_a, phi);
}

AlignedError AbsoluteTrajectoryError(const kernel::Trajectory& unsorted_truth,
                                     const kernel::Trajectory& estimate) {
  const kernel::Trajectory truth = kernel::SortedByTime(unsorted_truth);
  std::vector<Eigen::Vector2d> estimated, true_positions;
  std::vector<double> heading_differences;  // truth - estimate heading, before alignment
  for (const kernel::StampedPose& est : estimate) {
    const std::optional<kernel::Pose2> t = kernel::PoseAt(truth, est.time_s);
    if (!t) continue;
    estimated.push_back(est.pose.translation());
    true_positions.push_back(t->translation());
    heading_differences.push_back(kernel::WrapAngle(t->theta() - est.pose.theta()));
  }
  AlignedError e;
  e.matched = estimated.size();
  if (e.matched == 0) return e;
  if (e.matched >= 2) e.truth_T_estimate = AlignPoints(estimated, true_positions);
  std::vector<double> errors;
  double sum2 = 0.0, heading2 = 0.0;
  for (std::size_t i = 0; i < e.matched; ++i) {
    const double d = (e.truth_T_estimate * estimated[i] - true_positions[i]).norm();
    errors.push_back(d);
    sum2 += d * d;
    const double h = kernel::WrapAngle(heading_differences[i] - e.truth_T_estimate.theta());
    heading2 += h * h;
    e.max_m = std::max(e.max_m, d);
  }
  const auto n = static_cast<double>(e.matched);
  e.rmse_m = std::sqrt(sum2 / n);
  e.rmse_heading_rad = std::sqrt(heading2 / n);
  std::tie(e.mean_m, e.std_m) = MeanStd(errors);
  std::sort(errors.begin(), errors.end());
  const std::size_t mid = errors.size() / 2;
  e.median_m = errors.size() % 2 == 1 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
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
