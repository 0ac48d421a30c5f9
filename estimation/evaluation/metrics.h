#ifndef SPLAM_ESTIMATION_EVALUATION_METRICS_H_
#define SPLAM_ESTIMATION_EVALUATION_METRICS_H_

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/trajectory.h"

// Standard ways to score a SLAM run: against ground truth (simulated runs) and with the
// relations metric of Kümmerle et al. 2009 (logs with a .relations file).
namespace splam::evaluation {

// Mean and population standard deviation; (0, 0) for no values.
std::pair<double, double> MeanStd(const std::vector<double>& v);

struct TrajectoryError {
  std::size_t matched = 0;  // estimate poses with a truth pose at the same time
  double rmse_position_m = 0.0, max_position_m = 0.0;
  double rmse_heading_rad = 0.0, max_heading_rad = 0.0;
  // Per matched pose: estimate minus truth (heading wrapped).
  std::vector<double> time_s, error_x_m, error_y_m, error_theta_rad;
};

// Compares every estimate pose (in any order) with the truth at the same time (interpolated between
// truth poses at most 1 s apart). Both trajectories are in the same frame (simulated runs start the
// estimate at the true start pose).
TrajectoryError CompareToTruth(const kernel::Trajectory& truth, const kernel::Trajectory& estimate);

// The absolute trajectory error (ATE, Sturm et al. 2012, as evo's APE reports it) after the
// rigid alignment that fits the estimate best to the truth: the rotation and translation
// truth_T_estimate minimising sum_i |truth_i - T estimate_i|^2 over the positions matched in
// time (Umeyama 1991 / Horn 1987 in the plane, no scale). Headings are compared after the same
// rotation.
struct AlignedError {
  std::size_t matched = 0;         // estimate poses with a truth pose at the same time
  kernel::Pose2 truth_T_estimate;  // the alignment
  double rmse_m = 0.0, mean_m = 0.0, median_m = 0.0, std_m = 0.0, max_m = 0.0;
  double rmse_heading_rad = 0.0;
};
// Matches as CompareToTruth does; with fewer than 2 matches the alignment is the identity.
AlignedError AbsoluteTrajectoryError(const kernel::Trajectory& truth,
                                     const kernel::Trajectory& estimate);
// The planar rigid transform b_T_a minimising sum_i |b_i - b_T_a a_i|^2 (a.size() == b.size()):
// with centred points a', b', the angle atan2(sum a' x b', sum a' . b') and the translation that
// maps the centroid of a onto that of b.
kernel::Pose2 AlignPoints(const std::vector<Eigen::Vector2d>& a,
                          const std::vector<Eigen::Vector2d>& b);

// A relation: the motion from the pose at time t1 to the pose at t2, in the frame of the first.
struct Relation {
  double t1 = 0.0, t2 = 0.0;
  kernel::Pose2 motion;
};

struct RelationsError {
  std::size_t used = 0, skipped = 0;  // skipped: a time without an estimate pose
  // Translational error |t_rel - t_est| (m) and rotational error |wrap(yaw_rel - yaw_est)| (rad):
  // mean and standard deviation of the errors and of their squares.
  double translation_mean = 0.0, translation_std = 0.0;
  double translation_sq_mean = 0.0, translation_sq_std = 0.0;
  double rotation_mean = 0.0, rotation_std = 0.0;
  double rotation_sq_mean = 0.0, rotation_sq_std = 0.0;
};

// The relations metric: for every relation the same relative motion is computed from the
// estimate (in any order) (poses at t1 and t2: a pose stamped within 1 ms, else interpolated
// between poses less than 1 s apart; relations without both are skipped).
RelationsError EvaluateRelations(const std::vector<Relation>& relations,
                                 const kernel::Trajectory& estimate);

// Normalised estimation error squared of a pose: e^T P^-1 e with e = estimate - truth (heading
// wrapped). For a consistent filter it is chi-square distributed with 3 degrees of freedom.
double PoseNees(const kernel::Pose2& truth, const kernel::Pose2& estimate,
                const Eigen::Matrix3d& covariance);

}  // namespace splam::evaluation

#endif  // SPLAM_ESTIMATION_EVALUATION_METRICS_H_
