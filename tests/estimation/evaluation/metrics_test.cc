#include "estimation/evaluation/metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::evaluation {
namespace {

using kernel::Pose2;

TEST(CompareToTruth, ConstantOffsetGivesItsRmse) {
  kernel::Trajectory truth, estimate;
  for (int i = 0; i <= 10; ++i) {
    truth.push_back({i * 1.0, Pose2(i, 0, 0.1)});
    estimate.push_back({i * 1.0, Pose2(i + 0.3, -0.4, 0.1 + 0.05)});
  }
  estimate.push_back({20.0, Pose2()});  // no truth at t = 20: not matched
  const TrajectoryError e = CompareToTruth(truth, estimate);
  EXPECT_EQ(e.matched, 11u);
  EXPECT_NEAR(e.rmse_position_m, 0.5, 1e-12);
  EXPECT_NEAR(e.max_position_m, 0.5, 1e-12);
  EXPECT_NEAR(e.rmse_heading_rad, 0.05, 1e-12);
  EXPECT_NEAR(e.error_x_m[3], 0.3, 1e-12);
  EXPECT_NEAR(e.error_y_m[3], -0.4, 1e-12);
}

TEST(CompareToTruth, InterpolatesTruthBetweenStamps) {
  const kernel::Trajectory truth = {{0.0, Pose2(0, 0, 3.0)}, {1.0, Pose2(2, 0, -3.0)}};
  const TrajectoryError e = CompareToTruth(truth, {{0.5, Pose2(1, 0, -3.14159265)}});
  ASSERT_EQ(e.matched, 1u);
  EXPECT_NEAR(e.error_x_m[0], 0.0, 1e-12);
  // Halfway between 3.0 and -3.0 the short way round is pi.
  EXPECT_NEAR(e.error_theta_rad[0], 0.0, 1e-6);
}

// By hand: truth (0, 0), (2, 0); estimate (0, 1), (2, -1). Centred, a' = (-1, 1), (1, -1) and
// b' = (-1, 0), (1, 0): sum a'.b' = 2, sum a' x b' = 2, so the alignment turns by 45 deg. R a' =
// (-sqrt 2, 0), (sqrt 2, 0): each point sqrt 2 - 1 from its truth. The translation maps the
// centroid (1, 0) of the estimate onto (1, 0): t = (1, 0) - R (1, 0) = (1 - c, -s), c = s =
// 1/sqrt 2.
TEST(AbsoluteTrajectoryError, HandComputedAlignment) {
  const kernel::Trajectory truth = {{0.0, Pose2(0, 0, 0)}, {1.0, Pose2(2, 0, 0.2)}};
  const kernel::Trajectory estimate = {{0.0, Pose2(0, 1, 0.5)}, {1.0, Pose2(2, -1, 0.3)}};
  const AlignedError e = AbsoluteTrajectoryError(truth, estimate);
  const double c = std::sqrt(0.5);
  EXPECT_EQ(e.matched, 2u);
  EXPECT_NEAR(e.truth_T_estimate.theta(), kernel::kPi / 4, 1e-12);
  EXPECT_NEAR(e.truth_T_estimate.x(), 1 - c, 1e-12);
  EXPECT_NEAR(e.truth_T_estimate.y(), -c, 1e-12);
  EXPECT_NEAR(e.rmse_m, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(e.mean_m, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(e.median_m, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(e.max_m, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(e.std_m, 0.0, 1e-12);
  // Headings after the 45 deg turn: 0.5 + pi/4 vs 0, and 0.3 + pi/4 vs 0.2.
  const double h1 = 0.5 + kernel::kPi / 4, h2 = 0.1 + kernel::kPi / 4;
  EXPECT_NEAR(e.rmse_heading_rad, std::sqrt((h1 * h1 + h2 * h2) / 2), 1e-12);
}

// Any rigid motion of the truth, plus small noise, is undone: the error is the noise's, and the
// alignment is the motion's inverse (to the noise's effect).
TEST(AbsoluteTrajectoryError, PropertyRigidMotionsAreAlignedAway) {
  kernel::Random random(17);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 motion(random.Uniform(-50, 50), random.Uniform(-50, 50), random.Uniform(-3, 3));
    kernel::Trajectory truth, estimate;
    for (int i = 0; i < 50; ++i) {
      const Pose2 p(random.Uniform(-20, 20), random.Uniform(-20, 20), random.Uniform(-3, 3));
      truth.push_back({static_cast<double>(i), p});
      estimate.push_back({static_cast<double>(i), motion * p});
    }
    const AlignedError exact = AbsoluteTrajectoryError(truth, estimate);
    ASSERT_EQ(exact.matched, 50u);
    EXPECT_NEAR(exact.rmse_m, 0.0, 1e-9) << trial;
    EXPECT_NEAR(exact.rmse_heading_rad, 0.0, 1e-9) << trial;
    const Pose2 undo = exact.truth_T_estimate * motion;
    EXPECT_NEAR(undo.translation().norm(), 0.0, 1e-9) << trial;
    EXPECT_NEAR(kernel::WrapAngle(undo.theta()), 0.0, 1e-9) << trial;
    // Noise on the estimate: the ATE is at most the noise's RMS (the alignment can only lower it).
    double noise2 = 0.0;
    for (kernel::StampedPose& s : estimate) {
      const double dx = random.Gaussian(0.1);
      const double dy = random.Gaussian(0.1);
      s.pose = Pose2(s.pose.x() + dx, s.pose.y() + dy, s.pose.theta());
      noise2 += dx * dx + dy * dy;
    }
    const AlignedError noisy = AbsoluteTrajectoryError(truth, estimate);
    EXPECT_LE(noisy.rmse_m, std::sqrt(noise2 / 50) + 1e-12) << trial;
    EXPECT_GT(noisy.rmse_m, 0.5 * std::sqrt(noise2 / 50)) << trial;
  }
}

TEST(EvaluateRelations, ExactEstimateScoresZeroAndKnownErrorsScoreThemselves) {
  kernel::Random random(111);
  kernel::Trajectory truth;
  Pose2 p;
  for (int i = 0; i < 100; ++i) {
    truth.push_back({i * 0.1, p});
    p = p * Pose2(random.Uniform(0, 0.2), random.Uniform(-0.02, 0.02), random.Uniform(-0.1, 0.1));
  }
  std::vector<Relation> relations;
  for (int i = 0; i + 5 < 100; i += 3)
    relations.push_back(
        {truth[i].time_s, truth[i + 5].time_s, truth[i].pose.Between(truth[i + 5].pose)});
  relations.push_back({99.0, 100.0, Pose2()});  // times not in the trajectory
  const RelationsError exact = EvaluateRelations(relations, truth);
  EXPECT_EQ(exact.used, relations.size() - 1);
  EXPECT_EQ(exact.skipped, 1u);
  EXPECT_NEAR(exact.translation_mean, 0.0, 1e-12);
  EXPECT_NEAR(exact.rotation_mean, 0.0, 1e-12);
  // A relation off by (0.1, 0, 0.02) scores 0.1 m and 0.02 rad.
  const RelationsError off =
      EvaluateRelations({{truth[0].time_s, truth[1].time_s,
                          truth[0].pose.Between(truth[1].pose) * Pose2(0.1, 0, 0.02)}},
                        truth);
  EXPECT_NEAR(off.translation_mean, 0.1, 1e-9);
  EXPECT_NEAR(off.rotation_mean, 0.02, 1e-9);
  EXPECT_NEAR(off.translation_sq_mean, 0.01, 1e-9);
  EXPECT_EQ(off.translation_std, 0.0);
}

TEST(PoseNees, MatchesTheDefinition) {
  Eigen::Matrix3d p = Eigen::Vector3d(0.01, 0.04, 0.0025).asDiagonal();
  EXPECT_NEAR(PoseNees(Pose2(0, 0, 0), Pose2(0.1, 0.2, 0.05), p), 1 + 1 + 1, 1e-12);
  // Averaged over Gaussian errors drawn from P it is about 3 (the dof).
  kernel::Random random(112);
  double sum = 0;
  for (int i = 0; i < 20000; ++i) {
    sum += PoseNees(Pose2(),
                    Pose2(random.Gaussian(0.1), random.Gaussian(0.2), random.Gaussian(0.05)), p);
  }
  EXPECT_NEAR(sum / 20000, 3.0, 0.1);
}

}  // namespace
}  // namespace splam::evaluation
