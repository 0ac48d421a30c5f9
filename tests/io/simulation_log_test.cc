#include "io/simulation_log.h"

#include <gtest/gtest.h>

#include "sim/builtin_worlds.h"

namespace splam::io {
namespace {

TEST(MakeCarmenLog, SimulatedRunRoundTripsThroughTheLogFormat) {
  const sim::World world = *sim::BuiltinWorld("office");
  const sim::RayCaster caster(world);
  sim::SimulatorOptions options;
  options.enable_sonar = true;
  sim::Simulator simulator(caster, options, *world.start, 3);
  const sim::RouteRun run = sim::FollowRoute(&simulator, {world.route[0]}, sim::RouteOptions());
  ASSERT_TRUE(run.completed);
  const CarmenLog log = MakeCarmenLog(run.frames, options, {" test"});
  EXPECT_EQ(log.Lasers().size(), run.frames.size());
  EXPECT_EQ(log.Odometry().size(), run.frames.size());
  EXPECT_EQ(log.TruePoses().size(), run.frames.size());

  const CarmenReadResult read = ParseCarmenLog(FormatCarmenLog(log), "mem");
  ASSERT_TRUE(read.log.ok()) << read.log.error;
  const Trajectory truth = TrueTrajectory(*read.log.value);
  const Trajectory odometry = OdometryTrajectory(*read.log.value);
  ASSERT_EQ(truth.size(), run.frames.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(truth[i].pose.ToVector(), run.frames[i].true_pose.ToVector());
    EXPECT_EQ(odometry[i].pose.ToVector(), run.frames[i].odometry_pose.ToVector());
    EXPECT_EQ(truth[i].time_s, run.frames[i].time_s);
    const kernel::Scan& scan = read.log.value->Lasers()[i]->scan;
    ASSERT_EQ(scan.size(), run.frames[i].scan.size());
    for (std::size_t b = 0; b < scan.size(); ++b) {
      if (run.frames[i].scan.IsHit(b)) {
        EXPECT_EQ(scan.ranges_m[b], run.frames[i].scan.ranges_m[b]);
      } else {
        EXPECT_FALSE(scan.IsHit(b));
      }
    }
  }
}

TEST(OdometryTrajectory, FallsBackToLaserPosesWithoutOdom) {
  CarmenLog log;
  LaserMessage m;
  m.robot_pose = kernel::Pose2(1, 2, 3);
  m.stamp.ipc_timestamp_s = 5;
  log.messages.push_back(m);
  const Trajectory t = OdometryTrajectory(log);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].pose.x(), 1.0);
  EXPECT_EQ(t[0].time_s, 5.0);
  EXPECT_TRUE(TrueTrajectory(log).empty());
}

TEST(Route, StartPoseOrFirstWaypoint) {
  const Result<Route> with_start = ParseRoute("# route\n1 2 0.5\n3 4\n5 6\n", "r.txt");
  ASSERT_TRUE(with_start.ok()) << with_start.error;
  EXPECT_EQ(with_start.value->start.ToVector(), Eigen::Vector3d(1, 2, 0.5));
  EXPECT_EQ(with_start.value->waypoints.size(), 2u);
  const Result<Route> points = ParseRoute("0 0\n1 1\n", "r.txt");
  ASSERT_TRUE(points.ok());
  EXPECT_NEAR(points.value->start.theta(), M_PI / 4, 1e-15);
  EXPECT_EQ(points.value->waypoints.size(), 1u);
}

TEST(Route, AByteOrderMarkIsSkipped) {
  // A route saved by an editor with a UTF-8 BOM was refused ("'\xEF\xBB\xBF0' is
  // not a finite number") while logs and YAML with one were read.
  const Result<Route> r = ParseRoute(
      "\xEF\xBB\xBF"
      "0 0\n1 1\n",
      "r.txt");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->waypoints.size(), 1u);
}

TEST(Route, BadRoutesNameFileAndLine) {
  EXPECT_EQ(ParseRoute("0 0\n1 1 1\n", "r.txt").error, "r.txt:2: expected a waypoint 'x y'");
  EXPECT_EQ(ParseRoute("0 x\n", "r.txt").error, "r.txt:1: 'x' is not a finite number");
  // Control bytes are escaped, not echoed to the terminal.
  EXPECT_EQ(ParseRoute(std::string("0 x\0\x1b\n", 6), "r.txt").error,
            "r.txt:1: 'x\\x00\\x1b' is not a finite number");
  EXPECT_EQ(ParseRoute("1 2 3\n", "r.txt").error, "r.txt: the route has no waypoint");
  EXPECT_NE(ParseRoute("1 2\n", "r.txt").error.find("at least two waypoints"), std::string::npos);
  EXPECT_FALSE(ReadRoute("/nonexistent").ok());
}

}  // namespace
}  // namespace splam::io
