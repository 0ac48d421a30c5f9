// EKF-SLAM with lines and corners on synthetic observations whose truth is known exactly.
#include "estimation/ekf/ekf_line_slam.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::estimation {
namespace {

using kernel::LineExtraction;
using kernel::LineFeature;
using kernel::Pose2;

// A room of four walls (x = 0, x = 8, y = 0, y = 5) seen from `pose` without noise: every wall
// whose foot lies inside the room becomes a line feature with a 2 m extent around the foot.
LineExtraction SeeRoom(const Pose2& pose, kernel::Random* random = nullptr, double sigma = 0.0) {
  const Line walls[] = {
      {0.0, kernel::kPi}, {8.0, 0.0}, {0.0, -kernel::kPi / 2}, {5.0, kernel::kPi / 2}};
  LineExtraction out;
  for (const Line& w : walls) {
    // The foot of the perpendicular from the robot to the wall n . p = rho.
    const Eigen::Vector2d n(std::cos(w.theta), std::sin(w.theta));
    const Eigen::Vector2d on_wall = pose.translation() - (n.dot(pose.translation()) - w.rho) * n;
    const Line seen = TransformLine(pose.Inverse(), {w.rho, w.theta});
    LineFeature f;
    f.rho_m = seen.rho + (random ? random->Gaussian(sigma) : 0.0);
    f.theta_rad = seen.theta + (random ? random->Gaussian(sigma / 3.0) : 0.0);
    const Eigen::Vector2d t(-n.y(), n.x());
    f.start = pose.Inverse() * (on_wall - 1.0 * t);
    f.end = pose.Inverse() * (on_wall + 1.0 * t);
    f.covariance = Eigen::Vector2d(1e-4, 1e-5).asDiagonal();
    f.point_indices.resize(50);
    out.lines.push_back(f);
  }
  return out;
}

// Options that add landmarks at their first sighting, as the tests below expect.
EkfLineSlamOptions Immediate() {
  EkfLineSlamOptions options;
  options.min_observations_to_add = 1;
  return options;
}

TEST(EkfLineSlam, FirstScanCreatesLandmarksThenReobservationsAssociate) {
  EkfLineSlam slam(Pose2(3, 2, 0.3), Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  const UpdateReport first = slam.Update(SeeRoom(Pose2(3, 2, 0.3)), Pose2());
  EXPECT_EQ(first.new_landmarks, 4);
  EXPECT_EQ(slam.num_lines(), 4u);
  EXPECT_EQ(slam.state().size(), 3 + 8);
  const UpdateReport again = slam.Update(SeeRoom(Pose2(3, 2, 0.3)), Pose2());
  EXPECT_EQ(again.associated, 4);
  EXPECT_EQ(again.new_landmarks, 0);
  EXPECT_EQ(slam.num_lines(), 4u);
  // The map is the room, in normal form.
  for (const MapLine& l : slam.MapLines()) {
    EXPECT_GE(l.line.rho, 0.0);
    const bool vertical = std::abs(std::cos(l.line.theta)) > 0.99;
    EXPECT_NEAR(l.line.rho, vertical ? (l.line.rho > 4 ? 8.0 : 0.0) : (l.line.rho > 2 ? 5.0 : 0.0),
                1e-6);
  }
}

TEST(EkfLineSlam, PropertyCorrectsOdometryDriftAgainstTheMap) {
  // The robot drives 400 steps of loops inside the room (2 m straight, then a turn of 86 deg:
  // x in [1.3, 4.7] m, y in [0.8, 4.1] m); its odometry errors are drawn from the
  // filter's own noise model (scaled up 3x to make drift visible, and told to the filter), with
  // the default options. Seeing the walls keeps the estimate on the truth while dead reckoning
  // drifts away. Over 100 seeds the classic filter's known weakness shows: a heading draw of
  // 3.5 sigma or more in a turn puts every wall beyond the association gate at once, and the
  // walls seen again become new landmarks (a doubled map): 3 of these 100 seeds (measured
  // median error of the others 0.009 m, dead reckoning beyond 0.2 m in 73).
  constexpr int kSeeds = 100;
  int right_maps = 0, drifted = 0;
  std::vector<double> errors;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    EkfLineSlamOptions options;
    options.odometry = options.odometry.Scaled(3);
    EkfLineSlam slam(Pose2(2, 1, 0), Eigen::Matrix3d::Identity() * 1e-6, options);
    kernel::Random random(static_cast<std::uint64_t>(seed));
    Pose2 truth(2, 1, 0), dead_reckoning(2, 1, 0);
    slam.Update(SeeRoom(truth, &random, 0.005), Pose2());
    for (int step = 0; step < 400; ++step) {
      const Pose2 u(0.05, 0.0, step % 50 >= 40 ? 0.15 : 0.0);
      truth = truth * u;
      const Eigen::Matrix3d cov = options.odometry.Covariance(u);
      // Drawn one statement each: the order in which a call's arguments are evaluated is
      // unspecified (GCC and Clang differ), and the noise must not depend on the compiler.
      const double ex = random.Gaussian(std::sqrt(cov(0, 0)));
      const double ey = random.Gaussian(std::sqrt(cov(1, 1)));
      const double et = random.Gaussian(std::sqrt(cov(2, 2)));
      const Pose2 measured(u.x() + ex, u.y() + ey, u.theta() + et);
      dead_reckoning = dead_reckoning * measured;
      slam.Predict(measured);
      slam.Update(SeeRoom(truth, &random, 0.005), Pose2());
      ASSERT_TRUE(slam.healthy()) << slam.health().message();
    }
    const double error = (slam.pose().translation() - truth.translation()).norm();
    drifted += (dead_reckoning.translation() - truth.translation()).norm() > 0.2;
    if (slam.num_lines() != 4u) continue;
    ++right_maps;
    errors.push_back(error);
    EXPECT_LT(error, 0.1) << "seed " << seed;
    // The heading within four of the filter's own standard deviations: the run ends in a turn,
    // where a large draw may still be held off by the gate.
    EXPECT_LT(std::abs(kernel::WrapAngle(slam.pose().theta() - truth.theta())),
              4.0 * std::sqrt(slam.covariance()(2, 2)))
        << "seed " << seed;
    // The covariance stays symmetric and positive definite.
    const Eigen::MatrixXd& p = slam.covariance();
    EXPECT_LT((p - p.transpose()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues().minCoeff(), 0.0);
  }
  ASSERT_FALSE(errors.empty());
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2),
                   errors.end());
  const double median = errors[errors.size() / 2];
  EXPECT_GE(right_maps, 95);
  EXPECT_GE(drifted, 60);
  EXPECT_LT(median, 0.015);
}

TEST(EkfLineSlam, PredictionGrowsOnlyTheRobotUncertainty) {
  EkfLineSlam slam(Pose2(3, 2, 0), Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  slam.Update(SeeRoom(Pose2(3, 2, 0)), Pose2());
  const Eigen::MatrixXd before = slam.covariance();
  slam.Predict(Pose2(1.0, 0.0, 0.2));
  const Eigen::MatrixXd after = slam.covariance();
  EXPECT_GT(after(0, 0), before(0, 0));
  EXPECT_GT(after(2, 2), before(2, 2));
  // The landmark block is untouched.
  EXPECT_LT((after.bottomRightCorner(8, 8) - before.bottomRightCorner(8, 8)).cwiseAbs().maxCoeff(),
            1e-15);
  EXPECT_NEAR(slam.pose().x(), 4.0, 1e-12);
  EXPECT_NEAR(slam.pose().theta(), 0.2, 1e-12);
}

TEST(EkfLineSlam, OutliersAreRejectedOrBecomeNewLandmarksNotCorrections) {
  EkfLineSlam slam(Pose2(3, 2, 0), Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  slam.Update(SeeRoom(Pose2(3, 2, 0)), Pose2());
  LineExtraction odd = SeeRoom(Pose2(3, 2, 0));
  odd.lines[1].rho_m += 0.5;  // the wall at x = 8 seen 0.5 m too far: a different wall
  const Pose2 before = slam.pose();
  const UpdateReport r = slam.Update(odd, Pose2());
  EXPECT_EQ(r.associated, 3);
  EXPECT_EQ(r.new_landmarks, 1);
  EXPECT_LT(kernel::MaxAbsDifference(slam.pose(), before), 1e-6);
  // Short lines do not start landmarks.
  LineExtraction tiny = SeeRoom(Pose2(3, 2, 0));
  for (auto& l : tiny.lines) {
    l.rho_m += 1.0;
    l.end = l.start + 0.1 * (l.end - l.start).normalized();
  }
  const UpdateReport t = slam.Update(tiny, Pose2());
  EXPECT_EQ(t.new_landmarks, 0);
  EXPECT_EQ(t.too_small, 4);
}

TEST(EkfLineSlam, CornersAreLandmarksToo) {
  EkfLineSlam slam(Pose2(3, 2, 0.5), Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  LineExtraction features;
  features.corners.push_back(
      {Pose2(3, 2, 0.5).Inverse() * Eigen::Vector2d(8, 5), 0, 1, kernel::kPi / 2});
  EXPECT_EQ(slam.Update(features, Pose2()).new_landmarks, 1);
  EXPECT_EQ(slam.Update(features, Pose2()).associated, 1);
  ASSERT_EQ(slam.MapCorners().size(), 1u);
  EXPECT_LT((slam.MapCorners()[0].position - Eigen::Vector2d(8, 5)).norm(), 1e-9);
}

// Two corners 1 m apart across the robot's way, and a slip of 0.7 m sideways the odometry did
// not see (its lateral sigma 1 m per metre): corner B lies nearest landmark 1, so the nearest
// neighbour pairs B with 1 and then A with 2, both inside the gate, and the second correction
// drags landmark 2 half a metre onto landmark 1. JCBB pairs A with 1 and B with 2, the pairing
// one robot offset explains: the robot lands where it is and the map stays.
TEST(EkfLineSlam, JointCompatibilityUndoesTheNearestNeighboursCrossedPairing) {
  const Pose2 truth(1.0, 0.7, 0.0);
  const std::vector<Eigen::Vector2d> corners{{2.0, 0.0}, {2.0, 1.0}};
  const auto seen = [&](const Pose2& from) {
    LineExtraction features;
    for (const Eigen::Vector2d& c : corners)
      features.corners.push_back({from.Inverse() * c, 0, 1, kernel::kPi / 2});
    return features;
  };
  for (const EkfAssociation association :
       {EkfAssociation::kNearestNeighbour, EkfAssociation::kJointCompatibility}) {
    EkfLineSlamOptions options = Immediate();
    options.association = association;
    options.corner_max_distance_m = 2.0;
    options.odometry.lateral_per_m = 1.0;
    EkfLineSlam slam(Pose2(), Eigen::Matrix3d::Identity() * 1e-8, options);
    ASSERT_EQ(slam.Update(seen(Pose2()), Pose2()).new_landmarks, 2);
    slam.Predict(Pose2(1.0, 0.0, 0.0));
    const UpdateReport report = slam.Update(seen(truth), Pose2());
    EXPECT_EQ(report.associated, 2);
    const std::vector<MapCorner> map = slam.MapCorners();
    ASSERT_EQ(map.size(), 2u);
    const double moved =
        std::max((map[0].position - corners[0]).norm(), (map[1].position - corners[1]).norm());
    if (association == EkfAssociation::kJointCompatibility) {
      EXPECT_GT(report.jcbb_nodes, 0);
      EXPECT_LT((slam.pose().translation() - truth.translation()).norm(), 0.05);
      EXPECT_LT(moved, 0.05);
    } else {
      EXPECT_GT(moved, 0.3);
    }
  }
}

TEST(EkfLineSlam, LaserMountingIsTakenIntoAccount) {
  // The same room seen by a laser mounted 0.2 m ahead and turned 0.1 rad.
  const Pose2 robot(3, 2, 0.3), robot_T_laser(0.2, 0.0, 0.1);
  EkfLineSlam slam(robot, Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  LineExtraction seen = SeeRoom(robot * robot_T_laser);
  slam.Update(seen, robot_T_laser);
  for (const MapLine& l : slam.MapLines()) {
    const bool vertical = std::abs(std::cos(l.line.theta)) > 0.99;
    EXPECT_NEAR(l.line.rho, vertical ? (l.line.rho > 4 ? 8.0 : 0.0) : (l.line.rho > 2 ? 5.0 : 0.0),
                1e-6);
  }
}

TEST(EkfLineSlam, LandmarksEnterTheStateOnlyAfterRepeatedSightings) {
  EkfLineSlam slam(Pose2(3, 2, 0), Eigen::Matrix3d::Identity() * 1e-6);  // default: 3 sightings
  const LineExtraction room = SeeRoom(Pose2(3, 2, 0));
  EXPECT_EQ(slam.Update(room, Pose2()).candidates, 4);
  EXPECT_EQ(slam.num_lines(), 0u);
  EXPECT_EQ(slam.Update(room, Pose2()).candidates, 4);
  EXPECT_EQ(slam.Update(room, Pose2()).new_landmarks, 4);
  EXPECT_EQ(slam.num_lines(), 4u);
  EXPECT_EQ(slam.Update(room, Pose2()).associated, 4);
  // A line seen once (a person walking by) never enters the state, and is forgotten.
  LineExtraction once = room;
  once.lines.resize(1);
  once.lines[0].rho_m += 1.0;
  EXPECT_EQ(slam.Update(once, Pose2()).candidates, 1);
  for (int i = 0; i < 20; ++i) slam.Update(LineExtraction(), Pose2());
  EXPECT_EQ(slam.Update(once, Pose2()).candidates, 1);  // a fresh candidate again
  EXPECT_EQ(slam.num_lines(), 4u);
}

TEST(EkfLineSlam, ReobservedLinesExtendTheirExtent) {
  // SeeRoom sees 2 m of each wall around the foot of the perpendicular. Driving 2 m along x,
  // the walls y = 0 and y = 5 are seen from x = 2 to x = 6 in all.
  EkfLineSlam slam(Pose2(3, 2, 0), Eigen::Matrix3d::Identity() * 1e-6, Immediate());
  slam.Update(SeeRoom(Pose2(3, 2, 0)), Pose2());
  for (int step = 1; step <= 20; ++step) {
    slam.Predict(Pose2(0.1, 0, 0));
    slam.Update(SeeRoom(Pose2(3 + 0.1 * step, 2, 0)), Pose2());
  }
  ASSERT_EQ(slam.num_lines(), 4u);
  int horizontal = 0;
  for (const MapLine& l : slam.MapLines()) {
    if (std::abs(std::sin(l.line.theta)) < 0.99) continue;
    ++horizontal;
    EXPECT_NEAR(std::min(l.start.x(), l.end.x()), 2.0, 1e-3);
    EXPECT_NEAR(std::max(l.start.x(), l.end.x()), 6.0, 1e-3);
    EXPECT_NEAR(l.start.y(), l.end.y(), 1e-6);  // both ends on the wall
  }
  EXPECT_EQ(horizontal, 2);
}

TEST(EkfLineSlamOptions, Validate) {
  EXPECT_TRUE(EkfLineSlamOptions().Validate().ok());
  EkfLineSlamOptions o;
  o.new_landmark_probability = 0.5;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::estimation
