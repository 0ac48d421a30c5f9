#include "estimation/ekf/ekf_core.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "estimation/models.h"
#include "kernel/angle.h"

namespace splam::estimation {

EkfCore::EkfCore(const kernel::Pose2& initial_pose, const Eigen::Matrix3d& initial_covariance)
    : x_(initial_pose.ToVector()), p_(initial_covariance) {}

void EkfCore::Predict(const kernel::Pose2& u, const Eigen::Matrix3d& q_u) {
  if (!healthy()) return;
  MotionJacobians j;
  const kernel::Pose2 next = MotionModel(pose(), u, &j);
  x_.head<3>() = next.ToVector();
  const Eigen::Index m = x_.size() - 3;
  p_.topLeftCorner<3, 3>() =
      j.f_x * p_.topLeftCorner<3, 3>() * j.f_x.transpose() + j.f_u * q_u * j.f_u.transpose();
  if (m > 0) {
    p_.topRightCorner(3, m) = j.f_x * p_.topRightCorner(3, m);
    p_.bottomLeftCorner(m, 3) = p_.topRightCorner(3, m).transpose();
  }
  CheckHealth();
}

bool EkfCore::Correct(const Eigen::MatrixXd& h_robot, const std::vector<JacobianBlock>& blocks,
                      const Eigen::VectorXd& nu, const Eigen::MatrixXd& r) {
  if (!healthy()) return false;
  // P H^T touches only the robot columns and the blocks' columns.
  Eigen::MatrixXd pht = p_.leftCols<3>() * h_robot.transpose();
  for (const JacobianBlock& b : blocks) {
    pht.middleCols(b.first_row, b.jacobian.rows()).noalias() +=
        p_.middleCols(b.start, b.jacobian.cols()) * b.jacobian.transpose();
  }
  Eigen::MatrixXd s = h_robot * pht.topRows<3>() + r;
  for (const JacobianBlock& b : blocks) {
    s.middleRows(b.first_row, b.jacobian.rows()).noalias() +=
        b.jacobian * pht.middleRows(b.start, b.jacobian.cols());
  }
  s = 0.5 * (s + s.transpose()).eval();
  const Eigen::LLT<Eigen::MatrixXd> llt(s);
  if (llt.info() != Eigen::Success) return false;
  x_.noalias() += pht * llt.solve(nu);
  x_(2) = kernel::WrapAngle(x_(2));
  // P -= L L^T with L = P H^T U^-1, S = U^T U. A few rows (line and corner landmarks): one
  // full matrix product, a single pass over P. Many rows (the beams of a B-spline scan): update
  // the lower triangle only (half the arithmetic), then mirror it.
  const Eigen::MatrixXd l = llt.matrixU().transpose().solve(pht.transpose()).transpose();
  constexpr Eigen::Index kFewRows = 4;
  if (l.cols() <= kFewRows) {
    p_.noalias() -= l * l.transpose();
    // Rounding may break the symmetry slowly; restore it now and then.
    if (++corrections_ % 64 == 0) MirrorLowerTriangle();
  } else {
    p_.selfadjointView<Eigen::Lower>().rankUpdate(l, -1.0);
    MirrorLowerTriangle();
  }
  CheckHealth();
  return true;
}

void EkfCore::MirrorLowerTriangle() {
  // A block of columns at a time: transposing single rows would walk the column-major matrix
  // with a stride of N.
  constexpr Eigen::Index kBlock = 64;
  for (Eigen::Index j = 0; j < p_.cols(); j += kBlock) {
    const Eigen::Index w = std::min(kBlock, p_.cols() - j);
    auto diagonal = p_.block(j, j, w, w);
    diagonal.triangularView<Eigen::StrictlyUpper>() = diagonal.transpose();
    if (j > 0) p_.block(0, j, j, w) = p_.block(j, 0, w, j).transpose();
  }
}

Eigen::Index EkfCore::ReplaceBlock(Eigen::Index start, Eigen::Index size, const Eigen::VectorXd& g,
                                   const Eigen::MatrixXd& g_r, const Eigen::MatrixXd& g_b,
                                   const Eigen::MatrixXd& q) {
  const Eigen::Index n = x_.size();
  const Eigen::Index w = g.size();
  // Cross-covariance of the new block with the whole old state, and its own covariance.
  Eigen::MatrixXd cross = g_r * p_.topRows<3>();
  if (size > 0) cross.noalias() += g_b * p_.middleRows(start, size);
  Eigen::MatrixXd own = cross.leftCols<3>() * g_r.transpose() + q;
  if (size > 0) own.noalias() += cross.middleCols(start, size) * g_b.transpose();

  // The kept entries are [0, a) and [start + size, n), b of them after the block; copied as
  // blocks, which is much faster than index lists on large states.
  const Eigen::Index kept = n - size, a = start, b = n - start - size, after = start + size;
  Eigen::VectorXd x(kept + w);
  x.head(a) = x_.head(a);
  x.segment(a, b) = x_.tail(b);
  x.tail(w) = g;
  Eigen::MatrixXd p(kept + w, kept + w);
  p.topLeftCorner(a, a) = p_.topLeftCorner(a, a);
  p.block(0, a, a, b) = p_.block(0, after, a, b);
  p.block(a, 0, b, a) = p_.block(after, 0, b, a);
  p.block(a, a, b, b) = p_.block(after, after, b, b);
  p.block(kept, 0, w, a) = cross.leftCols(a);
  p.block(kept, a, w, b) = cross.rightCols(b);
  p.topRightCorner(kept, w) = p.bottomLeftCorner(w, kept).transpose();
  p.bottomRightCorner(w, w) = 0.5 * (own + own.transpose());
  x_ = std::move(x);
  p_ = std::move(p);
  CheckHealth();
  return kept;
}

void EkfCore::Negate(Eigen::Index i) {
  x_(i) = -x_(i);
  p_.row(i) *= -1.0;
  p_.col(i) *= -1.0;
}

void EkfCore::CheckHealth() {
  if (!health_.ok()) return;
  // The state and the diagonal only (O(N)): a non-finite covariance entry reaches the diagonal
  // with the next correction.
  if (!x_.allFinite() || !p_.diagonal().allFinite()) {
    health_ = kernel::Status::Error("state or covariance is not finite");
  } else if ((p_.diagonal().array() <= 0.0).any()) {
    health_ = kernel::Status::Error("covariance lost a positive diagonal entry");
  }
}

}  // namespace splam::estimation
