// The shared EKF arithmetic against the textbook dense formulas.
#include "estimation/ekf/ekf_core.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "kernel/random.h"

namespace splam::estimation {
namespace {

Eigen::MatrixXd RandomMatrix(Eigen::Index rows, Eigen::Index cols, kernel::Random* random) {
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) m(i, j) = random->Uniform(-1, 1);
  return m;
}
Eigen::MatrixXd RandomCovariance(Eigen::Index n, kernel::Random* random) {
  const Eigen::MatrixXd a = RandomMatrix(n, n, random);
  return a * a.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

// A filter with state x and covariance P: the pose from x, the landmarks appended as one block.
EkfCore MakeFilter(const Eigen::VectorXd& x, const Eigen::MatrixXd& p) {
  const Eigen::Index n = x.size();
  EkfCore ekf(kernel::Pose2(x(0), x(1), x(2)), p.topLeftCorner<3, 3>());
  Eigen::MatrixXd g_r = p.bottomLeftCorner(n - 3, 3) * p.topLeftCorner<3, 3>().inverse();
  ekf.Append(x.tail(n - 3), g_r,
             p.bottomRightCorner(n - 3, n - 3) - g_r * p.topRightCorner(3, n - 3));
  return ekf;
}

TEST(EkfCore, AppendReproducesAnyJointCovariance) {
  kernel::Random random(5);
  const Eigen::MatrixXd p = RandomCovariance(9, &random);
  Eigen::VectorXd x = RandomMatrix(9, 1, &random);
  const EkfCore ekf = MakeFilter(x, p);
  EXPECT_LT((ekf.covariance() - p).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((ekf.state() - x).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(EkfCore, PropertyCorrectionEqualsTheDenseFormulas) {
  kernel::Random random(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Index n = 3 + 2 * (2 + static_cast<Eigen::Index>(random.Index(8)));
    const Eigen::MatrixXd p = RandomCovariance(n, &random);
    Eigen::VectorXd x = RandomMatrix(n, 1, &random);
    x(2) = 0.1;  // far from the wrap-around
    EkfCore ekf = MakeFilter(x, p);
    const Eigen::Index k = 1 + static_cast<Eigen::Index>(random.Index(5));
    const Eigen::Index start = 3 + 2 * static_cast<Eigen::Index>(random.Index((n - 5) / 2));
    const Eigen::MatrixXd h_r = RandomMatrix(k, 3, &random);
    const Eigen::MatrixXd h_b = RandomMatrix(k, 2, &random);
    const Eigen::VectorXd nu = 0.01 * RandomMatrix(k, 1, &random);
    const Eigen::MatrixXd r = 0.1 * RandomCovariance(k, &random);
    ASSERT_TRUE(ekf.Correct(h_r, {JacobianBlock{start, h_b}}, nu, r));

    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(k, n);
    h.leftCols<3>() = h_r;
    h.middleCols(start, 2) = h_b;
    const Eigen::MatrixXd s = h * p * h.transpose() + r;
    const Eigen::MatrixXd gain = p * h.transpose() * s.inverse();
    const Eigen::VectorXd x_expected = x + gain * nu;
    const Eigen::MatrixXd p_expected = p - gain * s * gain.transpose();
    EXPECT_LT((ekf.state() - x_expected).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((ekf.covariance() - p_expected).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_EQ(ekf.covariance(), ekf.covariance().transpose());
  }
}

TEST(EkfCore, CorrectionRefusesAnIndefiniteInnovationCovariance) {
  EkfCore ekf(kernel::Pose2(1, 2, 0.3), Eigen::Matrix3d::Identity() * 1e-4);
  const Eigen::MatrixXd h = Eigen::RowVector3d(1, 0, 0);
  EXPECT_FALSE(ekf.Correct(h, {}, Eigen::VectorXd::Constant(1, 0.5), -Eigen::MatrixXd::Ones(1, 1)));
  EXPECT_EQ(ekf.pose().x(), 1.0);
}

TEST(EkfCore, PropertyReplaceBlockIsALinearisedTransformOfTheState) {
  // New state [x without block; g]: J = [selection; (G_r, 0.., G_b at the block, 0..)], and
  // P' = J P J^T + diag(0, Q).
  kernel::Random random(11);
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::Index n = 3 + 2 * (3 + static_cast<Eigen::Index>(random.Index(6)));
    const Eigen::MatrixXd p = RandomCovariance(n, &random);
    const Eigen::VectorXd x = RandomMatrix(n, 1, &random);
    EkfCore ekf = MakeFilter(x, p);
    const Eigen::Index start = 3 + 2 * static_cast<Eigen::Index>(random.Index(2));
    const Eigen::Index size = 4;
    const Eigen::Index w = 2 + 2 * static_cast<Eigen::Index>(random.Index(3));
    const Eigen::VectorXd g = RandomMatrix(w, 1, &random);
    const Eigen::MatrixXd g_r = RandomMatrix(w, 3, &random);
    const Eigen::MatrixXd g_b = RandomMatrix(w, size, &random);
    const Eigen::MatrixXd q = 0.01 * RandomCovariance(w, &random);
    const Eigen::Index at = ekf.ReplaceBlock(start, size, g, g_r, g_b, q);
    ASSERT_EQ(at, n - size);

    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n - size + w, n);
    for (Eigen::Index i = 0, row = 0; i < n; ++i) {
      if (i < start || i >= start + size) j(row++, i) = 1.0;
    }
    j.bottomLeftCorner(w, 3) = g_r;
    j.block(n - size, start, w, size) = g_b;
    Eigen::MatrixXd p_expected = j * p * j.transpose();
    p_expected.bottomRightCorner(w, w) += q;
    EXPECT_LT((ekf.covariance() - p_expected).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((ekf.state().head(n - size) - (j.topRows(n - size) * x)).cwiseAbs().maxCoeff(),
              1e-15);
    EXPECT_EQ(ekf.state().tail(w), g);
  }
}

TEST(EkfCore, NegateFlipsTheEntryAndItsCorrelations) {
  kernel::Random random(13);
  const Eigen::MatrixXd p = RandomCovariance(7, &random);
  const Eigen::VectorXd x = RandomMatrix(7, 1, &random);
  EkfCore ekf = MakeFilter(x, p);
  ekf.Negate(4);
  Eigen::MatrixXd d = Eigen::MatrixXd::Identity(7, 7);
  d(4, 4) = -1;
  EXPECT_LT((ekf.covariance() - d * p * d).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(ekf.state()(4), -x(4));
}

}  // namespace
}  // namespace splam::estimation
