// Every Jacobian of the EKF models against central differences.
#include "estimation/models.h"

#include <gtest/gtest.h>

#include <functional>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;
using kernel::Random;
using kernel::WrapAngle;

// Numeric Jacobian of f: R^n -> R^m at v; outputs flagged in `angles` are differenced with
// wrapping.
template <int M, int N>
Eigen::Matrix<double, M, N> Numeric(
    const std::function<Eigen::Matrix<double, M, 1>(const Eigen::Matrix<double, N, 1>&)>& f,
    const Eigen::Matrix<double, N, 1>& v, std::vector<int> angles = {}) {
  Eigen::Matrix<double, M, N> j;
  const double h = 1e-6;
  for (int c = 0; c < N; ++c) {
    Eigen::Matrix<double, N, 1> a = v, b = v;
    a(c) += h;
    b(c) -= h;
    Eigen::Matrix<double, M, 1> d = f(a) - f(b);
    for (int r : angles) d(r) = WrapAngle(d(r));
    j.col(c) = d / (2 * h);
  }
  return j;
}

Pose2 RandomPose(Random* r) {
  return Pose2(r->Uniform(-5, 5), r->Uniform(-5, 5), r->Uniform(-3.1, 3.1));
}

TEST(MotionModel, MatchesPoseCompositionAndJacobiansAreRight) {
  Random random(101);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 x = RandomPose(&random);
    const Pose2 u(random.Uniform(-0.3, 0.3), random.Uniform(-0.1, 0.1), random.Uniform(-0.5, 0.5));
    MotionJacobians j;
    EXPECT_LT(kernel::MaxAbsDifference(MotionModel(x, u, &j), x * u), 1e-12);
    const auto fx = Numeric<3, 3>(
        [&](const Eigen::Vector3d& v) {
          return MotionModel(Pose2(v(0), v(1), v(2)), u).ToVector();
        },
        x.ToVector(), {2});
    const auto fu = Numeric<3, 3>(
        [&](const Eigen::Vector3d& v) {
          return MotionModel(x, Pose2(v(0), v(1), v(2))).ToVector();
        },
        u.ToVector(), {2});
    EXPECT_LT((fx - j.f_x).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LT((fu - j.f_u).cwiseAbs().maxCoeff(), 1e-7);
  }
}

TEST(OdometryNoiseModel, ProportionalToMotionWithFloors) {
  const OdometryNoiseModel m;
  const Eigen::Matrix3d still = m.Covariance(Pose2());
  EXPECT_NEAR(still(0, 0), 1e-8, 1e-20);
  const Eigen::Matrix3d moving = m.Covariance(Pose2(1.0, 0.0, 0.5));
  EXPECT_NEAR(std::sqrt(moving(0, 0)), 0.03 + 1e-4, 1e-12);
  EXPECT_NEAR(std::sqrt(moving(1, 1)), 0.01 + 1e-4, 1e-12);
  EXPECT_NEAR(std::sqrt(moving(2, 2)), 0.03 * 0.5 + 0.01 + 1e-4, 1e-12);
  EXPECT_TRUE(m.Validate().ok());
}

TEST(Lines, TransformLineMovesItsPoints) {
  Random random(102);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 a_T_b = RandomPose(&random);
    const Line l{random.Uniform(0, 5), random.Uniform(-3.1, 3.1)};
    const Line m = TransformLine(a_T_b, l);
    EXPECT_GE(m.rho, 0.0);
    // Two points of the line in b map onto the line in a.
    const Eigen::Vector2d n(std::cos(l.theta), std::sin(l.theta)), t(-n.y(), n.x());
    for (double s : {-2.0, 3.0}) {
      const Eigen::Vector2d p = a_T_b * (l.rho * n + s * t);
      EXPECT_NEAR(std::cos(m.theta) * p.x() + std::sin(m.theta) * p.y(), m.rho, 1e-9);
    }
  }
}

TEST(Lines, PredictLineJacobiansIncludingTheFlippedSide) {
  Random random(103);
  int flipped = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Pose2 x = RandomPose(&random);
    const Line l{random.Uniform(0, 6), random.Uniform(-3.1, 3.1)};
    Matrix23 h_r;
    Eigen::Matrix2d h_l;
    const Eigen::Vector2d h = PredictLine(x, l, &h_r, &h_l);
    if (std::abs(l.rho - x.x() * std::cos(l.theta) - x.y() * std::sin(l.theta)) < 1e-3)
      continue;  // on the line
    flipped += l.rho - x.x() * std::cos(l.theta) - x.y() * std::sin(l.theta) < 0;
    EXPECT_GE(h(0), 0.0);
    // The prediction is the observed line: the world line seen from the robot frame.
    const Line seen = TransformLine(x.Inverse(), l);
    EXPECT_NEAR(h(0), seen.rho, 1e-9);
    EXPECT_NEAR(WrapAngle(h(1) - seen.theta), 0.0, 1e-9);
    const auto nr = Numeric<2, 3>(
        [&](const Eigen::Vector3d& v) { return PredictLine(Pose2(v(0), v(1), v(2)), l); },
        x.ToVector(), {1});
    const auto nl = Numeric<2, 2>(
        [&](const Eigen::Vector2d& v) {
          return PredictLine(x, {v(0), v(1)});
        },
        Eigen::Vector2d(l.rho, l.theta), {1});
    EXPECT_LT((nr - h_r).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
    EXPECT_LT((nl - h_l).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
  }
  EXPECT_GT(flipped, 50);
}

TEST(Lines, PropertyALineThroughTheSensorHasASmallInnovationInEitherForm) {
  // Walls passing within 1 cm of the sensor, observed with noise and predicted from a pose a few
  // millimetres off: each side's normal form may have either sign. The innovation must stay
  // small, and be a smooth function of the pose whose Jacobian is the (turned) h_r.
  Random random(105);
  int turned = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Pose2 x = RandomPose(&random);
    const double theta = random.Uniform(-3.1, 3.1);
    const Eigen::Vector2d n(std::cos(theta), std::sin(theta));
    const Line world =
        TransformLine(Pose2(), {n.dot(x.translation()) + random.Uniform(-0.01, 0.01), theta});
    const Line seen = TransformLine(x.Inverse(), world);
    const double noise_rho = random.Gaussian(0.003);
    const double noise_theta = random.Gaussian(0.002);
    const Line z = TransformLine(Pose2(), {seen.rho + noise_rho, seen.theta + noise_theta});
    const double ox = random.Gaussian(0.003), oy = random.Gaussian(0.003);
    const double oth = random.Gaussian(0.002);
    const Pose2 estimate(x.x() + ox, x.y() + oy, x.theta() + oth);
    Matrix23 h_r;
    Eigen::Matrix2d h_l;
    const Eigen::Vector2d zv(z.rho, z.theta);
    const Eigen::Vector2d h = PredictLine(estimate, world, &h_r, &h_l);
    turned += std::abs(WrapAngle(zv(1) - h(1))) > kernel::kPi / 2;
    const Eigen::Vector2d nu = LineInnovation(zv, h, &h_r, &h_l);
    EXPECT_LT(std::abs(nu(0)), 0.05) << "trial " << trial;
    EXPECT_LT(std::abs(nu(1)), 0.02) << "trial " << trial;
    const auto nr = Numeric<2, 3>(
        [&](const Eigen::Vector3d& v) {
          return Eigen::Vector2d(-LineInnovation(zv, PredictLine(Pose2(v(0), v(1), v(2)), world)));
        },
        estimate.ToVector(), {1});
    const auto nl = Numeric<2, 2>(
        [&](const Eigen::Vector2d& v) {
          return Eigen::Vector2d(-LineInnovation(zv, PredictLine(estimate, {v(0), v(1)})));
        },
        Eigen::Vector2d(world.rho, world.theta), {1});
    EXPECT_LT((nr - h_r).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
    if (world.rho > 1e-3) {  // the world line's own sign flip is not differentiable at rho = 0
      EXPECT_LT((nl - h_l).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
    }
  }
  EXPECT_GT(turned, 50);  // the case arises: the two forms disagree in sign
}

TEST(Lines, InitializeLineInvertsPredictionAndJacobiansAreRight) {
  Random random(104);
  for (int trial = 0; trial < 500; ++trial) {
    const Pose2 x = RandomPose(&random);
    const Line z{random.Uniform(0.2, 6), random.Uniform(-3.1, 3.1)};
    Matrix23 g_r;
    Eigen::Matrix2d g_z;
    const Line g = InitializeLine(x, z, &g_r, &g_z);
    EXPECT_GE(g.rho, 0.0);
    const Eigen::Vector2d back = PredictLine(x, g);
    EXPECT_NEAR(back(0), z.rho, 1e-9);
    EXPECT_NEAR(WrapAngle(back(1) - z.theta), 0.0, 1e-9);
    auto as_vector = [](const Line& l) { return Eigen::Vector2d(l.rho, l.theta); };
    const auto nr = Numeric<2, 3>(
        [&](const Eigen::Vector3d& v) {
          return as_vector(InitializeLine(Pose2(v(0), v(1), v(2)), z));
        },
        x.ToVector(), {1});
    const auto nz = Numeric<2, 2>(
        [&](const Eigen::Vector2d& v) {
          return as_vector(InitializeLine(x, {v(0), v(1)}));
        },
        as_vector(z), {1});
    if (g.rho < 1e-3) continue;  // the sign flip is not differentiable at rho = 0
    EXPECT_LT((nr - g_r).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
    EXPECT_LT((nz - g_z).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
  }
}

TEST(Points, PredictAndInitializeAreInversesWithRightJacobians) {
  Random random(105);
  for (int trial = 0; trial < 300; ++trial) {
    const Pose2 x = RandomPose(&random);
    const Eigen::Vector2d c(random.Uniform(-8, 8), random.Uniform(-8, 8));
    Matrix23 h_r, g_r;
    Eigen::Matrix2d h_c, g_z;
    const Eigen::Vector2d z = PredictPoint(x, c, &h_r, &h_c);
    EXPECT_LT((z - x.Inverse() * c).norm(), 1e-12);
    EXPECT_LT((InitializePoint(x, z, &g_r, &g_z) - c).norm(), 1e-12);
    const auto nr = Numeric<2, 3>(
        [&](const Eigen::Vector3d& v) { return PredictPoint(Pose2(v(0), v(1), v(2)), c); },
        x.ToVector());
    const auto nc = Numeric<2, 2>([&](const Eigen::Vector2d& v) { return PredictPoint(x, v); }, c);
    const auto ngr = Numeric<2, 3>(
        [&](const Eigen::Vector3d& v) { return InitializePoint(Pose2(v(0), v(1), v(2)), z); },
        x.ToVector());
    const auto ngz =
        Numeric<2, 2>([&](const Eigen::Vector2d& v) { return InitializePoint(x, v); }, z);
    EXPECT_LT((nr - h_r).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((nc - h_c).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((ngr - g_r).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((ngz - g_z).cwiseAbs().maxCoeff(), 1e-6);
  }
}

}  // namespace
}  // namespace splam::estimation
