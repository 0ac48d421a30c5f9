#include "examples/estimation/scan_matcher.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "kernel/angle.h"

namespace my_lab {
namespace {

using splam::kernel::Pose2;

// One Gauss-Newton step of point-to-line ICP: the motion T that minimises
// sum (n_i . (T a_i - b_i))^2 / sigma_p^2 + (T - guess)^T W (T - guess) (a_i in the current
// frame; b_i a keyframe point with the normal n_i of the keyframe's surface there), linearised
// at T. The odometry guess with its information W holds the directions the points leave free
// (the length of a corridor) and weighs the two sources by their noise.
Pose2 PointToLineStep(const Pose2& t, const Pose2& guess, const Eigen::Matrix3d& w, double sigma_p,
                      const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                      const std::vector<Eigen::Vector2d>& n) {
  Eigen::Matrix3d jtj = w * sigma_p * sigma_p;  // everything in units of the point noise
  Eigen::Vector3d jtr = jtj * Eigen::Vector3d(t.x() - guess.x(), t.y() - guess.y(),
                                              splam::kernel::WrapAngle(t.theta() - guess.theta()));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d q = t * a[i];
    const Eigen::Vector2d dq_dtheta(-(q - t.translation()).y(), (q - t.translation()).x());
    const Eigen::Vector3d j(n[i].x(), n[i].y(), n[i].dot(dq_dtheta));
    jtj += j * j.transpose();
    jtr += j * n[i].dot(q - b[i]);
  }
  const Eigen::Vector3d delta = -jtj.ldlt().solve(jtr);
  return Pose2(t.translation() + delta.head<2>(), t.theta() + delta.z());
}

// The surface normal at every point of a scan (beam order): the direction of least spread of its
// 2 w + 1 neighbours (principal components); zero where they span a gap wider than max_span_m.
// Each point with a normal is moved onto the line of its neighbours (their range noise averaged).
std::vector<Eigen::Vector2d> Normals(std::vector<Eigen::Vector2d>* surface, int w,
                                     double max_span_m) {
  const std::vector<Eigen::Vector2d> points = *surface;
  std::vector<Eigen::Vector2d> normals(points.size(), Eigen::Vector2d::Zero());
  const std::size_t half = static_cast<std::size_t>(w);
  for (std::size_t i = half; i + half < points.size(); ++i) {
    if ((points[i + half] - points[i - half]).norm() > max_span_m) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t k = i - half; k <= i + half; ++k) mean += points[k];
    mean /= static_cast<double>(2 * half + 1);
    Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
    for (std::size_t k = i - half; k <= i + half; ++k)
      spread += (points[k] - mean) * (points[k] - mean).transpose();
    normals[i] = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(spread).eigenvectors().col(0);
    (*surface)[i] -= normals[i] * normals[i].dot(points[i] - mean);
  }
  return normals;
}

}  // namespace

void ScanMatcherOptions::VisitFields(splam::kernel::FieldVisitor& v) {
  v.Field("iterations", &iterations, "ICP rounds per scan");
  v.Field("beam_step", &beam_step, "every beam_step-th hit takes part");
  v.Field("max_pair_distance_m", &max_pair_distance_m, "nearest neighbours paired within, m");
  v.Field("normal_half_window", &normal_half_window, "normals from 2 w + 1 neighbouring hits");
  v.Field("point_sigma_m", &point_sigma_m, "noise of a point-to-line distance, m");
  v.Field("odometry_sigma_fraction", &odometry_sigma_fraction,
          "odometry sigma per m travelled and rad turned");
  v.Field("odometry_sigma_floor", &odometry_sigma_floor, "odometry sigma floor, m and rad");
  v.Field("min_pairs", &min_pairs, "fewer pairs keep the odometry");
  v.Field("keyframe_distance_m", &keyframe_distance_m, "new keyframe after this much motion, m");
  v.Field("keyframe_angle_rad", &keyframe_angle_rad, "... or this much turning, rad");
  v.Field("max_correction_m", &max_correction_m, "larger corrections are refused, m");
  v.Field("max_correction_rad", &max_correction_rad, "larger corrections are refused, rad");
}

splam::kernel::Status ScanMatcherOptions::Validate() const {
  if (iterations < 1 || beam_step < 1 || min_pairs < 3)
    return splam::kernel::Status::Error("iterations, beam_step >= 1, min_pairs >= 3");
  if (!(max_pair_distance_m > 0) || !(max_correction_m > 0) || !(max_correction_rad > 0))
    return splam::kernel::Status::Error("distances must be positive");
  return splam::kernel::Status::Ok();
}

ScanMatcher::ScanMatcher(const ScanMatcherOptions& options,
                         const splam::estimation::SlamContext& context)
    : options_(options), pose_(context.start), key_pose_(context.start) {}

void ScanMatcher::Predict(const Pose2& odometry_increment) {
  pose_ = pose_ * odometry_increment;
  since_previous_ = since_previous_ * odometry_increment;
}

void ScanMatcher::Update(const splam::kernel::Scan& scan, const Pose2& robot_T_laser) {
  const std::vector<Eigen::Vector2d> current = robot_T_laser * scan.HitPoints();
  if (previous_.empty()) {  // the first keyframe
    previous_ = current;
    normals_ = Normals(&previous_, options_.normal_half_window, 4.0 * options_.max_pair_distance_m);
    key_pose_ = pose_;
    since_previous_ = Pose2();
    return;
  }
  // ICP: keyframe_T_current starts at the odometry and is refined by pairing each point with its
  // nearest keyframe point and that point's surface normal.
  Pose2 estimate = since_previous_;
  bool aligned = previous_.size() >= 3;
  // The odometry since the keyframe: sigma grows with the distance and the turn (the simulator's
  // model has 3 % of both), with a floor.
  const double d = since_previous_.translation().norm(), turn = std::abs(since_previous_.theta());
  const double sigma_t = options_.odometry_sigma_floor + options_.odometry_sigma_fraction * d;
  const double sigma_r =
      options_.odometry_sigma_floor + options_.odometry_sigma_fraction * (turn + d);
  const Eigen::Matrix3d odometry_information =
      Eigen::Vector3d(1 / (sigma_t * sigma_t), 1 / (sigma_t * sigma_t), 1 / (sigma_r * sigma_r))
          .asDiagonal();
  for (int round = 0; aligned && round < options_.iterations; ++round) {
    std::vector<Eigen::Vector2d> from, to, normals;
    for (std::size_t k = 0; k < current.size(); k += static_cast<std::size_t>(options_.beam_step)) {
      const Eigen::Vector2d q = estimate * current[k];
      double best = options_.max_pair_distance_m * options_.max_pair_distance_m;
      std::size_t nearest = previous_.size();
      for (std::size_t r = 0; r < previous_.size(); ++r) {
        if ((previous_[r] - q).squaredNorm() < best && normals_[r] != Eigen::Vector2d::Zero())
          best = (previous_[r] - q).squaredNorm(), nearest = r;
      }
      if (nearest == previous_.size()) continue;
      from.push_back(current[k]);
      to.push_back(previous_[nearest]);
      normals.push_back(normals_[nearest]);
    }
    aligned = static_cast<int>(from.size()) >= options_.min_pairs;
    if (aligned)
      estimate = PointToLineStep(estimate, since_previous_, odometry_information,
                                 options_.point_sigma_m, from, to, normals);
  }
  const Pose2 correction = since_previous_.Between(estimate);
  if (aligned && correction.translation().norm() <= options_.max_correction_m &&
      std::abs(correction.theta()) <= options_.max_correction_rad) {
    pose_ = key_pose_ * estimate;
    ++aligned_;
  } else {
    estimate = since_previous_;  // keep the odometry
    ++refused_;
  }
  // A new keyframe once the robot has moved far enough from the last one: errors then add up
  // per keyframe, not per scan.
  if (estimate.translation().norm() > options_.keyframe_distance_m ||
      std::abs(estimate.theta()) > options_.keyframe_angle_rad) {
    previous_ = current;
    normals_ = Normals(&previous_, options_.normal_half_window, 4.0 * options_.max_pair_distance_m);
    key_pose_ = pose_;
    since_previous_ = Pose2();
  }
}

splam::estimation::SlamStatistics ScanMatcher::Statistics() const {
  splam::estimation::SlamStatistics s;
  s.associations = {{"aligned_scans", aligned_}, {"kept_odometry", refused_}};
  return s;
}

}  // namespace my_lab
