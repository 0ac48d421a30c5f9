#include "kernel/pose2.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

Pose2 RandomPose(Random* random) {
  return Pose2(random->Uniform(-50, 50), random->Uniform(-50, 50), random->Uniform(-kPi, kPi));
}

TEST(Pose2, ConstructorWrapsTheAngle) {
  const Pose2 p(1.0, 2.0, 3.0 * kPi);
  EXPECT_NEAR(p.theta(), kPi, 1e-12);
  EXPECT_EQ(p.ToVector(), Eigen::Vector3d(1.0, 2.0, p.theta()));
}

TEST(Pose2, TransformsPoints) {
  const Pose2 world_T_robot(1.0, 2.0, kPi / 2.0);
  const Eigen::Vector2d p = world_T_robot * Eigen::Vector2d(1.0, 0.0);
  EXPECT_NEAR(p.x(), 1.0, 1e-15);
  EXPECT_NEAR(p.y(), 3.0, 1e-15);
  const auto points = world_T_robot * std::vector<Eigen::Vector2d>{{0, 0}, {0, 1}};
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[1].x(), 0.0, 1e-15);
  EXPECT_NEAR(points[1].y(), 2.0, 1e-15);
}

TEST(Pose2, ComposesLikeTheMotionModel) {
  // SPEC §2: x' = x + dx cos th - dy sin th, y' = y + dx sin th + dy cos th, th' = th + dth.
  const Pose2 pose(1.0, -2.0, 0.3);
  const Pose2 u(0.5, 0.1, 0.2);
  const Pose2 next = pose * u;
  EXPECT_NEAR(next.x(), 1.0 + 0.5 * std::cos(0.3) - 0.1 * std::sin(0.3), 1e-15);
  EXPECT_NEAR(next.y(), -2.0 + 0.5 * std::sin(0.3) + 0.1 * std::cos(0.3), 1e-15);
  EXPECT_NEAR(next.theta(), 0.5, 1e-15);
}

TEST(Pose2, PropertyComposeWithInverseIsIdentity) {
  Random random(1);
  for (int i = 0; i < 1000; ++i) {
    const Pose2 p = RandomPose(&random);
    EXPECT_LT(MaxAbsDifference(p * p.Inverse(), Pose2()), 1e-12);
    EXPECT_LT(MaxAbsDifference(p.Inverse() * p, Pose2()), 1e-12);
  }
}

TEST(Pose2, PropertyComposeIsAssociativeAndBetweenInverts) {
  Random random(2);
  for (int i = 0; i < 1000; ++i) {
    const Pose2 a = RandomPose(&random), b = RandomPose(&random), c = RandomPose(&random);
    EXPECT_LT(MaxAbsDifference((a * b) * c, a * (b * c)), 1e-9);
    EXPECT_LT(MaxAbsDifference(a * a.Between(b), b), 1e-9);
    const Eigen::Vector2d p(random.Uniform(-5, 5), random.Uniform(-5, 5));
    EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-9);
    EXPECT_LT((a.Inverse() * (a * p) - p).norm(), 1e-9);
  }
}

TEST(Pose2, RotationIsOrthonormal) {
  const Eigen::Matrix2d r = Pose2(0, 0, 0.7).Rotation();
  EXPECT_TRUE((r * r.transpose()).isApprox(Eigen::Matrix2d::Identity(), 1e-15));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
}

TEST(MaxAbsDifference, UsesWrappedAngles) {
  EXPECT_NEAR(MaxAbsDifference(Pose2(0, 0, kPi - 0.01), Pose2(0, 0, -kPi + 0.01)), 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(MaxAbsDifference(Pose2(1, 0, 0), Pose2(0, 3, 0)), 3.0);
}

}  // namespace
}  // namespace splam::kernel
