// EKF-SLAM with B-splines on the simulator, whose truth is known exactly.
#include "estimation/ekf/ekf_bspline_slam.h"

#include <gtest/gtest.h>

#include <string>

#include <Eigen/Eigenvalues>
#include <memory>

#include "estimation/evaluation/metrics.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"
#include "tests/estimation/map_error.h"

namespace splam::estimation {
namespace {
using evaluation::CompareToTruth;
using evaluation::TrajectoryError;

using test_util::MapError;

struct DriveResult {
  kernel::Trajectory truth, estimate, odometry;
  std::vector<MapSpline> map;
  int created = 0, extended = 0;
  std::unique_ptr<EkfBSplineSlam> slam;
};

// Drives `world`'s route (at most max_scans scans) with a URG-04LX and runs the filter.
DriveResult Drive(const sim::World& world, const EkfBSplineSlamOptions& options, int max_scans,
                  std::uint64_t seed) {
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Urg04lx();
  sim::Simulator simulator(caster, sim_options, *world.start, seed);
  sim::RouteOptions route;
  route.max_steps = max_scans - 1;
  const sim::RouteRun r = sim::FollowRoute(&simulator, world.route, route);
  DriveResult run;
  run.slam = std::make_unique<EkfBSplineSlam>(
      *world.start, Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal(), options);
  EkfBSplineSlam* slam = run.slam.get();
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const sim::SensorFrame& f = r.frames[i];
    if (i > 0) slam->Predict(r.frames[i - 1].odometry_pose.Between(f.odometry_pose));
    const BSplineUpdateReport report = slam->Update(f.scan);
    EXPECT_TRUE(slam->healthy()) << slam->health().message();
    run.created += static_cast<int>(report.created.size());
    run.extended += static_cast<int>(report.extended.size());
    run.truth.push_back({f.time_s, f.true_pose});
    run.estimate.push_back({f.time_s, slam->pose()});
    run.odometry.push_back({f.time_s, f.odometry_pose});
  }
  run.map = slam->MapSplines();
  return run;
}

class BothAssociations : public testing::TestWithParam<const char*> {};

TEST_P(BothAssociations, MapsTheComplexWorldAndCorrectsOdometry) {
  const sim::World world = *sim::BuiltinWorld("complex");
  EkfBSplineSlamOptions options;
  std::string association = GetParam();
  if (association.ends_with("+jcbb")) {  // the matches chosen by joint compatibility
    options.match_selection = "jcbb";
    association.resize(association.size() - 5);
  }
  options.association = association;
  const DriveResult run = Drive(world, options, 2000, 3);  // the whole route
  const TrajectoryError e = CompareToTruth(run.truth, run.estimate);
  const TrajectoryError o = CompareToTruth(run.truth, run.odometry);
  EXPECT_LT(e.rmse_position_m, 0.05);
  EXPECT_LT(e.rmse_position_m, 0.5 * o.rmse_position_m);
  EXPECT_LT(e.max_heading_rad, 0.02);
  EXPECT_GE(run.map.size(), 5u);
  EXPECT_GT(run.extended, 0);
  EXPECT_LT(MapError(world, run.map), 0.05);  // odometry alone drifts 0.4 m
  // The covariance stays symmetric and positive definite.
  const Eigen::MatrixXd& p = run.slam->covariance();
  EXPECT_EQ(p, p.transpose());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues().minCoeff(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(EkfBSplineSlam, BothAssociations,
                         testing::Values("pedraza", "curvature", "curvature+jcbb"));

TEST(EkfBSplineSlam, OneWallSeenBitByBitIsOneExtendedSpline) {
  // A straight wall along y = 1 from x = -1 to 14; the robot drives along y = 0 from x = 0 to 10
  // with a 4 m laser, so the wall comes into view piece by piece: one spline, extended, that
  // covers what was seen and lies on the wall.
  sim::World world;
  world.obstacles.push_back(sim::Polyline{{{-1, 1}, {14, 1}}, false});
  world.start = kernel::Pose2(0, 0, 0);
  world.route = {{10, 0}};
  EkfBSplineSlamOptions options;
  const DriveResult run = Drive(world, options, 400, 5);
  ASSERT_EQ(run.map.size(), 1u);
  EXPECT_GT(run.extended, 5);
  const kernel::CubicBSpline& s = run.map[0].spline;
  const Eigen::Vector2d a = s.Point(s.DomainStart()), b = s.Point(s.DomainEnd());
  EXPECT_LT(std::min(a.x(), b.x()), -0.25);
  EXPECT_GT(std::max(a.x(), b.x()), 12.5);
  EXPECT_LT(MapError(world, run.map), 0.02);  // range noise: 1-4 cm
  const TrajectoryError e = CompareToTruth(run.truth, run.estimate);
  EXPECT_LT(e.rmse_position_m, 0.1);
}

TEST(EkfBSplineSlam, NewSplinesNeedRepeatedSightings) {
  const sim::World world = *sim::BuiltinWorld("complex");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.laser = sim::LaserOptions::Urg04lx();
  sim::Simulator simulator(caster, sim_options, *world.start, 1);
  EkfBSplineSlamOptions options;
  options.min_observations_to_add = 3;
  EkfBSplineSlam slam(*world.start, Eigen::Matrix3d::Identity() * 1e-6, options);
  const kernel::Scan scan = simulator.Sense().scan;
  EXPECT_TRUE(slam.Update(scan).created.empty());
  EXPECT_GT(slam.Update(scan).candidates, 0);
  EXPECT_EQ(slam.num_splines(), 0u);
  const BSplineUpdateReport third = slam.Update(scan);
  EXPECT_GT(third.created.size(), 0u);
  EXPECT_EQ(slam.num_splines(), third.created.size());
  EXPECT_EQ(slam.state().size(), 3 + 2 * static_cast<Eigen::Index>(slam.num_control_points()));
  // The same scan again associates with the new splines and leaves the pose where it is.
  const BSplineUpdateReport fourth = slam.Update(scan);
  EXPECT_TRUE(fourth.created.empty());
  EXPECT_GT(fourth.beams_used, 30);
  EXPECT_LT((slam.pose().translation() - world.start->translation()).norm(), 0.01);
}

TEST(EkfBSplineSlamOptions, Validate) {
  EXPECT_TRUE(EkfBSplineSlamOptions().Validate().ok());
  EkfBSplineSlamOptions o;
  o.association = "nearest";
  EXPECT_FALSE(o.Validate().ok());
  o = EkfBSplineSlamOptions();
  o.max_beams_per_match = 0;
  EXPECT_FALSE(o.Validate().ok());
  o = EkfBSplineSlamOptions();
  o.range_sigma_fraction = o.model_sigma_m = 0.0;
  EXPECT_FALSE(o.Validate().ok());
  // A filter with invalid options says so and ignores input instead of crashing.
  o = EkfBSplineSlamOptions();
  o.association = "nearest";
  EkfBSplineSlam slam(kernel::Pose2(), Eigen::Matrix3d::Identity(), o);
  EXPECT_FALSE(slam.healthy());
  EXPECT_NE(slam.health().message().find("association"), std::string::npos);
  kernel::Scan scan;
  scan.angular_step_rad = 0.01;
  scan.max_range_m = 4.0;
  scan.ranges_m.assign(100, 2.0);
  EXPECT_EQ(slam.Update(scan).observed_curves, 0);
}

}  // namespace
}  // namespace splam::estimation
