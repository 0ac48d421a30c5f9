#ifndef SPLAM_ESTIMATION_EKF_EKF_CORE_H_
#define SPLAM_ESTIMATION_EKF_EKF_CORE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/status.h"

// The filter arithmetic shared by the EKF-SLAM variants: a state X = [x, y, th, landmarks...]
// with full covariance P, odometry prediction, corrections whose Jacobian touches the robot and
// a few landmark blocks, and replacing or appending landmark blocks (SPEC §4, §8).
namespace splam::estimation {

// One nonzero block of a measurement Jacobian H: rows [first_row, first_row + jacobian.rows()),
// columns [start, start + jacobian.cols()).
struct JacobianBlock {
  Eigen::Index start = 0;
  Eigen::MatrixXd jacobian;
  Eigen::Index first_row = 0;
};

class EkfCore {
 public:
  EkfCore(const kernel::Pose2& initial_pose, const Eigen::Matrix3d& initial_covariance);

  // Prediction with an odometry increment u (robot frame) of covariance q_u through the motion
  // model of SPEC §2: the robot block and the robot-landmark cross-covariances change, O(N).
  void Predict(const kernel::Pose2& u, const Eigen::Matrix3d& q_u);

  // Correction with innovation nu (k) and noise R (k x k), H = [h_robot, 0..] + the blocks
  // (which must not reach into the robot columns; they may overlap each other and then add up):
  //   S = H P H^T + R,  K = P H^T S^-1,  X += K nu,  P -= (P H^T) S^-1 (P H^T)^T,
  // the last as one rank-k update (O(k N^2), no N x N temporaries). The heading is wrapped
  // afterwards. False, with the state unchanged, when S is not positive definite.
  bool Correct(const Eigen::MatrixXd& h_robot, const std::vector<JacobianBlock>& blocks,
               const Eigen::VectorXd& nu, const Eigen::MatrixXd& r);

  // Replaces the landmark block [start, start + size) by g = f(robot, block, measurements), with
  // G_r = df/drobot (w' x 3), G_b = df/dblock (w' x size) and q the covariance the measurements
  // add (G_z R G_z^T). The old block is removed and the new one appended at the end of the
  // state; landmarks behind the old block move `size` entries forward. size 0 appends (SLAM
  // augmentation, P_new = G_r P_rr G_r^T + q). Returns the new block's start.
  Eigen::Index ReplaceBlock(Eigen::Index start, Eigen::Index size, const Eigen::VectorXd& g,
                            const Eigen::MatrixXd& g_r, const Eigen::MatrixXd& g_b,
                            const Eigen::MatrixXd& q);
  Eigen::Index Append(const Eigen::VectorXd& g, const Eigen::MatrixXd& g_r,
                      const Eigen::MatrixXd& q) {
    return ReplaceBlock(x_.size(), 0, g, g_r, Eigen::MatrixXd(g.size(), 0), q);
  }

  // x(i) -> -x(i): flips the sign of row and column i of P too.
  void Negate(Eigen::Index i);

  kernel::Pose2 pose() const { return kernel::Pose2(x_(0), x_(1), x_(2)); }
  Eigen::Matrix3d pose_covariance() const { return p_.topLeftCorner<3, 3>(); }
  const Eigen::VectorXd& state() const { return x_; }
  Eigen::VectorXd& mutable_state() { return x_; }
  const Eigen::MatrixXd& covariance() const { return p_; }

  // False once the state or covariance is not finite or P lost positive diagonal entries.
  bool healthy() const { return health_.ok(); }
  const kernel::Status& health() const { return health_; }
  void CheckHealth();
  // Marks the filter unhealthy with this message (e.g. invalid options); it then ignores input.
  void Fail(std::string message) {
    if (health_.ok()) health_ = kernel::Status::Error(std::move(message));
  }

 private:
  // P's upper triangle from its lower one.
  void MirrorLowerTriangle();

  Eigen::VectorXd x_;
  Eigen::MatrixXd p_;
  kernel::Status health_;
  std::size_t corrections_ = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_EKF_CORE_H_
