#include "sim/simulator.h"

#include <gtest/gtest.h>

#include "kernel/angle.h"

namespace splam::sim {
namespace {

// A 10 m x 6 m room: four walls as an open polyline (a closed polygon would be a solid block).
World Box() {
  World w;
  w.obstacles.push_back(Polyline{{{0, 0}, {10, 0}, {10, 6}, {0, 6}, {0, 0}}, false});
  return w;
}

TEST(Simulator, StepMovesTruthExactlyAndOdometryWithNoise) {
  const RayCaster caster(Box());
  SimulatorOptions options;
  Simulator sim(caster, options, kernel::Pose2(2, 3, 0), 1);
  ASSERT_TRUE(sim.Step(0.5, 0.0));
  EXPECT_NEAR(sim.true_pose().x(), 2.05, 1e-12);
  EXPECT_NEAR(sim.time_s(), 0.1, 1e-15);
  EXPECT_NE(sim.odometry_pose().x(), sim.true_pose().x());
  EXPECT_NEAR(sim.odometry_pose().x(), 2.05, 0.01);
}

TEST(Simulator, CollisionStopsTheRobot) {
  const RayCaster caster(Box());
  Simulator sim(caster, SimulatorOptions(), kernel::Pose2(9.6, 3, 0), 1);
  ASSERT_TRUE(sim.IsFree(sim.true_pose()));
  int steps = 0;
  while (sim.Step(0.5, 0.0)) ++steps;
  EXPECT_EQ(steps, 2);  // 9.65, 9.70; 9.75 would touch the wall at 10 with radius 0.267
  EXPECT_NEAR(sim.true_pose().x(), 9.70, 1e-12);
  EXPECT_FALSE(sim.IsFree(kernel::Pose2(9.9, 3, 0)));
}

TEST(Simulator, CommandsAreClampedToTheRobotLimits) {
  const RayCaster caster(Box());
  Simulator sim(caster, SimulatorOptions(), kernel::Pose2(2, 3, 0), 1);
  ASSERT_TRUE(sim.Step(100.0, 0.0));
  EXPECT_NEAR(sim.true_pose().x(), 2.0 + 1.2 * 0.1, 1e-12);
}

TEST(FollowRoute, ReachesEveryWaypointAndIsReproducible) {
  const RayCaster caster(Box());
  const std::vector<Eigen::Vector2d> route = {{8, 1.5}, {8, 4.5}, {2, 4.5}};
  auto run = [&](std::uint64_t seed) {
    Simulator sim(caster, SimulatorOptions(), kernel::Pose2(2, 1.5, 0), seed);
    return FollowRoute(&sim, route, RouteOptions());
  };
  const RouteRun a = run(5), b = run(5), c = run(6);
  ASSERT_TRUE(a.completed) << a.message;
  EXPECT_EQ(a.waypoints_reached, 3);
  EXPECT_LT((a.frames.back().true_pose.translation() - route.back()).norm(), 0.1);
  EXPECT_NEAR(a.distance_m, 6 + 3 + 6, 0.3);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(a.frames[i].odometry_pose.ToVector(), b.frames[i].odometry_pose.ToVector());
    EXPECT_EQ(a.frames[i].scan.ranges_m, b.frames[i].scan.ranges_m);
  }
  EXPECT_NE(a.frames.back().odometry_pose.ToVector(), c.frames.back().odometry_pose.ToVector());
  // Frames are 0.1 s apart and start at the start pose.
  EXPECT_EQ(a.frames[0].time_s, 0.0);
  EXPECT_NEAR(a.frames[1].time_s, 0.1, 1e-15);
}

TEST(FollowRoute, ReportsCollisionsAndTheStepCap) {
  World w = Box();
  w.obstacles.push_back(Polyline{{{5, 0}, {5, 6}}, false});  // a wall across the room
  const RayCaster caster(w);
  Simulator sim(caster, SimulatorOptions(), kernel::Pose2(2, 3, 0), 1);
  const RouteRun blocked = FollowRoute(&sim, {{8, 3}}, RouteOptions());
  EXPECT_FALSE(blocked.completed);
  EXPECT_NE(blocked.message.find("collision"), std::string::npos);

  const RayCaster open(Box());
  Simulator slow(open, SimulatorOptions(), kernel::Pose2(2, 3, 0), 1);
  RouteOptions capped;
  capped.max_steps = 10;
  const RouteRun run = FollowRoute(&slow, {{8, 3}}, capped);
  EXPECT_FALSE(run.completed);
  EXPECT_NE(run.message.find("max_steps = 10"), std::string::npos);
  EXPECT_EQ(run.frames.size(), 11u);
}

TEST(Simulator, SonarFramesWhenEnabled) {
  const RayCaster caster(Box());
  SimulatorOptions options;
  options.enable_sonar = true;
  Simulator sim(caster, options, kernel::Pose2(2, 3, 0), 1);
  const SensorFrame frame = sim.Sense();
  EXPECT_EQ(frame.sonar_ranges_m.size(), 16u);
  EXPECT_EQ(frame.scan.size(), 667u);
  EXPECT_EQ(frame.beam_obstacles.size(), 667u);
}

TEST(SimulatorOptions, Validate) {
  EXPECT_TRUE(SimulatorOptions().Validate().ok());
  SimulatorOptions o;
  o.time_step_s = 0;
  EXPECT_FALSE(o.Validate().ok());
  EXPECT_FALSE(RouteOptions{.max_steps = 0}.Validate().ok());
}

}  // namespace
}  // namespace splam::sim
