#ifndef SPLAM_ESTIMATION_EKF_JOINT_COMPATIBILITY_H_
#define SPLAM_ESTIMATION_EKF_JOINT_COMPATIBILITY_H_

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "estimation/ekf/ekf_core.h"

// Joint compatibility branch and bound (JCBB; Neira and Tardós 2001) for the EKFs' data
// association: of the pairings that pass the individual gate, the largest set whose innovations
// are jointly compatible, instead of the nearest neighbour's one pairing at a time.
namespace splam::estimation {

// A pairing (an observation with a landmark, or for the B-spline EKF an observed curve's stretch
// with a map spline) as the filter's correction would use it: innovation nu (rows), Jacobian
// H = [h_robot, 0, ...] + blocks (rows of each block from its first_row, within this item), noise.
struct CompatibilityItem {
  int group = 0;  // items of one group exclude each other (one observation: one landmark)
  Eigen::VectorXd innovation;
  Eigen::MatrixXd h_robot;  // rows x 3
  std::vector<JacobianBlock> blocks;
  Eigen::MatrixXd noise;  // rows x rows
};

struct JointCompatibilityResult {
  std::vector<int> chosen;  // indices of the items taken, ascending
  double d2 = 0.0;          // their joint squared Mahalanobis distance
  long nodes = 0;           // hypotheses tested
  bool exhaustive = true;   // false when max_nodes cut the search short (the best so far)
};

// The largest set of items, no two of one group and none that `conflict` (a landmark paired
// twice), whose stacked innovation passes the joint gate
//   D^2 = nu_H^T (H_H P H_H^T + R_H)^-1 nu_H <= chi^2(rows of H, probability),
// found depth-first over the items in the order given (put each group's most likely first): an
// item is taken before it is left out, and a branch is cut when even every remaining group could
// not make a larger set (Neira and Tardós). Of equally large sets the one of smaller D^2 replaces
// the one found first only where the search reaches it before that cut: the answer is the
// largest set, not necessarily of the smallest D^2 among those as large. `covariance` is the filter's
// P (the items' columns index it). At most max_nodes hypotheses are tested.
JointCompatibilityResult JointCompatibility(const std::vector<CompatibilityItem>& items,
                                            const std::function<bool(int, int)>& conflict,
                                            const Eigen::MatrixXd& covariance, double probability,
                                            long max_nodes = 100000);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_JOINT_COMPATIBILITY_H_
