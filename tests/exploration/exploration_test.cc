// Exploration: sonar-completed LSRs, MOVE_TO, coverage, and SRT / REG end to end in the simulator.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "exploration/coverage.h"
#include "exploration/explorer.h"
#include "exploration/localization.h"
#include "exploration/motion.h"
#include "exploration/perception.h"
#include "exploration/reg.h"
#include "exploration/session.h"
#include "exploration/srt.h"
#include "exploration/steps.h"
#include "io/floor_plan.h"
#include "kernel/angle.h"
#include "kernel/random.h"
#include "runtime/simulated_robot.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"

namespace splam::exploration {
namespace {

// A robot without obstacles: exact unicycle motion, perfect odometry.
class FreeRobot : public RobotInterface {
 public:
  explicit FreeRobot(const kernel::Pose2& start) : pose_(start) {}
  const RobotDescription& description() const override { return description_; }
  bool Step(double v, double w) override {
    pose_ = pose_ * kernel::UnicycleIncrement(v, w, description_.time_step_s);
    time_ += description_.time_step_s;
    return true;
  }
  Perception ReadOdometry() override { return {time_, pose_, pose_, {}, {}}; }
  Perception Sense() override { return ReadOdometry(); }
  const kernel::Pose2& pose() const { return pose_; }

 private:
  RobotDescription description_;
  kernel::Pose2 pose_;
  double time_ = 0.0;
};

TEST(MoveTo, PropertyReachesTheGoalAlongTheLegFromAnyHeading) {
  kernel::Random random(3);
  const MotionOptions options;
  for (int trial = 0; trial < 50; ++trial) {
    const kernel::Pose2 start(random.Uniform(-5, 5), random.Uniform(-5, 5),
                              random.Uniform(-kernel::kPi, kernel::kPi));
    const double angle = random.Uniform(-kernel::kPi, kernel::kPi);
    const Eigen::Vector2d goal =
        start.translation() +
        random.Uniform(0.5, 3.0) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    FreeRobot robot(start);
    OdometryLocalization localization;
    ASSERT_EQ(localization.Start(robot.description(), start, robot.ReadOdometry()).message(), "");
    kernel::Pose2 estimate = start;
    std::vector<TraceSample> trace;
    const MoveResult result =
        MoveTo({goal}, start.translation(), options, &robot, &localization, &estimate, &trace);
    ASSERT_TRUE(result.reached) << "trial " << trial << ": " << result.message;
    EXPECT_LE((robot.pose().translation() - goal).norm(), options.goal_tolerance_m + 1e-9);
    // The robot turns first, then drives: it never strays far from the straight leg.
    const Eigen::Vector2d d = (goal - start.translation()).normalized();
    for (const TraceSample& s : trace) {
      const Eigen::Vector2d p = s.truth.translation() - start.translation();
      EXPECT_LT(std::abs(d.x() * p.y() - d.y() * p.x()), 0.06) << "trial " << trial;
    }
  }
}

TEST(TurnTowards, PropertyFacesTheTargetInPlace) {
  kernel::Random random(5);
  const MotionOptions options;
  for (int trial = 0; trial < 50; ++trial) {
    const kernel::Pose2 start(random.Uniform(-5, 5), random.Uniform(-5, 5),
                              random.Uniform(-kernel::kPi, kernel::kPi));
    const double angle = random.Uniform(-kernel::kPi, kernel::kPi);
    const Eigen::Vector2d target =
        start.translation() +
        random.Uniform(0.3, 3.0) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    FreeRobot robot(start);
    OdometryLocalization localization;
    ASSERT_EQ(localization.Start(robot.description(), start, robot.ReadOdometry()).message(), "");
    kernel::Pose2 estimate = start;
    std::vector<TraceSample> trace;
    ASSERT_TRUE(TurnTowards(target, options, &robot, &localization, &estimate, &trace));
    // Within half the smallest turn of a step (0.15 rad/s x 0.1 s), and where it stood.
    EXPECT_LE(std::abs(kernel::WrapAngle(angle - robot.pose().theta())), 0.0075 + 1e-9)
        << "trial " << trial;
    EXPECT_LT((robot.pose().translation() - start.translation()).norm(), 1e-12);
    // The shorter way round: about |angle error| / 0.8 rad/s, plus the slow steps at the end.
    const double turn = std::abs(kernel::WrapAngle(angle - start.theta()));
    EXPECT_LE(static_cast<double>(trace.size()), turn / 0.08 + 4) << "trial " << trial;
  }
}

TEST(SafeRegionScan, SonarsCompleteTheCircleBehindTheLaser) {
  RobotDescription robot;
  robot.robot_T_sonar = {kernel::Pose2(-0.2, 0.0, kernel::kPi)};  // one sonar looking back
  robot.sonar_cone_half_angle_rad = kernel::DegToRad(15.0);
  Perception p;
  p.scan.start_angle_rad = -kernel::DegToRad(90.0);
  p.scan.angular_step_rad = kernel::DegToRad(1.0);
  p.scan.max_range_m = 4.0;
  p.scan.ranges_m.assign(181, 2.0);
  p.sonar_ranges_m = {1.0};
  const kernel::Scan scan = SafeRegionScan(p, robot);
  ASSERT_EQ(scan.size(), 360u);
  EXPECT_EQ(scan.ranges_m[90], 2.0);  // laser beams unchanged
  // Straight back: the sonar's free sector reaches 0.2 + 1.0 from the laser.
  EXPECT_NEAR(scan.ranges_m[270], 1.2, 1e-9);
  // Outside the cone only the robot's disc is known free.
  EXPECT_NEAR(scan.ranges_m[200], robot.radius_m, 1e-9);
  // No echo: free beyond the laser's range.
  p.sonar_ranges_m = {kernel::Scan::kNoReturn};
  EXPECT_TRUE(std::isinf(SafeRegionScan(p, robot).ranges_m[270]));
}

TEST(CoverageGrid, AFullCircleRegionCoversItsAreaOfAnOpenRoom) {
  const kernel::Box2 room{{0, 0}, {10, 10}};
  CoverageGrid grid(room, 0.1, {5, 5}, [](const Eigen::Vector2d&) { return true; });
  EXPECT_EQ(grid.reachable_cells(), 10000);
  kernel::Scan scan;
  scan.start_angle_rad = -kernel::kPi;
  scan.angular_step_rad = 2 * kernel::kPi / 720;
  scan.ranges_m.assign(720, kernel::Scan::kNoReturn);
  grid.Cover(kernel::LocalSafeRegion::FromScan(scan, kernel::Pose2(5, 5, 0), 2.0));
  // The disc of radius 2 m plus at most the band of boundary cells (one cell wide).
  EXPECT_GE(grid.CoveredFraction(), kernel::kPi * 2.0 * 2.0 / 100.0);
  EXPECT_LE(grid.CoveredFraction(), kernel::kPi * 2.1 * 2.1 / 100.0);
  // A wall splits the room: only the start's side is reachable.
  CoverageGrid half(room, 0.1, {2, 5},
                    [](const Eigen::Vector2d& c) { return c.x() < 4.9 || c.x() > 5.1; });
  EXPECT_EQ(half.reachable_cells(), 4900);
}

struct Trial {
  ExplorationRun run;
  double coverage = 0.0;
};

// `own`: the explorer's own options (SrtOptions, RegOptions), its defaults when null.
Trial ExploreWorld(const std::string& explorer, const sim::World& world, std::uint64_t seed,
                   const ExplorerOptions& options = {}, bool odometry = false,
                   const kernel::AnyOptions* own = nullptr) {
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.enable_sonar = true;
  sim::Simulator simulator(caster, sim_options, *world.start, seed);
  runtime::SimulatedRobot robot(&simulator);
  GroundTruthLocalization truth;
  OdometryLocalization dead_reckoning;
  ExplorerOptions o = options;
  o.seed = seed;
  Trial trial;
  trial.run = std::move(*ExplorerRegistry::Global().Make(explorer, o, own).value)
                  ->Run(&robot, odometry ? static_cast<Localization*>(&dead_reckoning) : &truth);
  kernel::Box2 bounds = world.Bounds();
  CoverageGrid grid(bounds, 0.1, world.start->translation(), [&](const Eigen::Vector2d& c) {
    return !caster.IsInsideObstacle(c) && caster.Nearest(c, 0.0708).obstacle < 0;
  });
  for (const NodeRecord& node : trial.run.nodes)
    grid.Cover(
        SafeRegionAt(node.safe_region_scan, node.true_pose, robot.description(), o.lsr_radius_m));
  trial.coverage = grid.CoveredFraction();
  return trial;
}

Trial Explore(const std::string& explorer, const std::string& world_name, std::uint64_t seed,
              const ExplorerOptions& options = {}, bool odometry = false,
              const kernel::AnyOptions* own = nullptr) {
  return ExploreWorld(explorer, *sim::BuiltinWorld(world_name), seed, options, odometry, own);
}

// Whether a node of the run lies in the box [lo, hi].
bool NodeIn(const ExplorationRun& run, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  for (graph::Vertex v = 0; v < run.graph.num_nodes(); ++v) {
    const Eigen::Vector2d p = run.graph[v].configuration.translation();
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) return true;
  }
  return false;
}

// The causes of rooms left unexplored (docs/experiments.md, Fig. 18), each on a small hand-made
// world. A corridor 1.8 m wide with a 4 m x 6.5 m room south of it behind a 0.9 m door at
// x 5.6-6.5, deeper than the LSR radius; the robot starts at the corridor's west end, so its first
// nodes see the door at a slant.
sim::World CorridorAndRoom() {
  sim::World w;
  w.name = "corridor-and-room";
  using V = Eigen::Vector2d;
  w.obstacles.push_back(
      sim::Polyline{{V(5.6, 0), V(0, 0), V(0, 1.8), V(9, 1.8), V(9, 0), V(6.5, 0)}, false});
  w.obstacles.push_back(sim::Polyline{{V(4, 0), V(4, -6.5), V(8, -6.5), V(8, 0)}, false});
  w.start = kernel::Pose2(0.8, 0.9, 0.0);
  return w;
}

TEST(ExplorationCauses, ARoomSeenThroughItsDoorAtASlantIsEntered) {
  for (const std::string explorer : {"reg", "srt"}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const Trial t = ExploreWorld(explorer, CorridorAndRoom(), seed);
      EXPECT_TRUE(NodeIn(t.run, {4.3, -6.2}, {7.7, -0.5}))
          << explorer << " seed " << seed << ": " << t.run.graph.num_nodes() << " nodes, "
          << t.coverage << " covered, " << t.run.message;
      EXPECT_GT(t.coverage, 0.98) << explorer << " seed " << seed;
      EXPECT_EQ(t.run.termination, Termination::kExplored) << t.run.message;
    }
  }
}

// A 12 m x 8 m floor drawn at 5 cm per pixel, as a user would scan one: walls 10 cm thick, a
// corridor along y 3.5-5.2 m, two rooms south and two north behind 0.9 m doors, a desk in the
// south-west room; read back with io::ReadFloorPlan, the robot at the corridor's west end.
sim::World FloorPlanRooms() {
  const double px = 0.05;
  cv::Mat image(160, 240, CV_8U, cv::Scalar(255));
  const auto P = [&](double x, double y) {  // world metres to the pixel (y up)
    return cv::Point(static_cast<int>(std::lround(x / px)),
                     static_cast<int>(std::lround((8.0 - y) / px)) - 1);
  };
  const auto wall = [&](double x0, double y0, double x1, double y1) {
    cv::rectangle(image, P(x0, y0), P(x1, y1), cv::Scalar(0), cv::FILLED);
  };
  wall(0, 0, 12, 0.1), wall(0, 7.9, 12, 8), wall(0, 0, 0.1, 8), wall(11.9, 0, 12, 8);
  wall(0, 3.5, 2.0, 3.6), wall(2.9, 3.5, 8.0, 3.6), wall(8.9, 3.5, 12, 3.6);  // south doors
  wall(0, 5.2, 3.5, 5.3), wall(4.4, 5.2, 9.0, 5.3), wall(9.9, 5.2, 12, 5.3);  // north doors
  wall(6.0, 0, 6.1, 3.5), wall(6.5, 5.3, 6.6, 8);
  wall(2.0, 1.0, 3.6, 1.8);  // a desk
  const std::string path = ::testing::TempDir() + "/floor_plan_rooms.png";
  EXPECT_TRUE(cv::imwrite(path, image));
  kernel::Result<sim::World> world = io::ReadFloorPlan(path, io::FloorPlanOptions());
  EXPECT_TRUE(world.ok()) << world.error;
  if (!world.ok()) return {};
  world.value->start = kernel::Pose2(1.0, 4.35, 0.0);
  return *world.value;
}

TEST(ExplorationCauses, RoomsOfAFloorPlanImageAreExplored) {
  const sim::World world = FloorPlanRooms();
  // Measured: 3 of 4 seeds reach 98 % (seed 2: 89 %, incomplete, a given-up arc;
  // docs/experiments.md).
  int complete = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const Trial t = ExploreWorld("reg", world, seed);
    complete += t.coverage > 0.98;
    EXPECT_GT(t.coverage, 0.85) << "seed " << seed;
    // A done that means done: `explored` only where the run did explore.
    if (t.run.termination == Termination::kExplored) {
      EXPECT_GT(t.coverage, 0.98) << "seed " << seed;
    }
    EXPECT_TRUE(NodeIn(t.run, {6.3, 0.3}, {11.7, 3.3})) << "seed " << seed;  // south-east room
    EXPECT_TRUE(NodeIn(t.run, {0.3, 5.5}, {6.3, 7.7})) << "seed " << seed;   // north-west room
  }
  EXPECT_GE(complete, 3);
}

TEST(ExplorationCauses, SpaceClosedOnlyByTheSonarsIsLookedAt) {
  // The floor plan, seed 1, with look_before_giving_up: the robot enters the south-west room
  // facing south-west, away from the room's east half; the sonars' first echoes (off the desk's
  // corner) close that half of its LSR, no free arc or shadow leads there, and the laser never
  // looks at it. Counted as seen, the run ended `explored` at 88 %. As an unseen stretch
  // (unseen_frontiers), it is looked at and the east half entered. Since the union walk no longer
  // takes a region on again where the ray left it (kernel::UnionSeesBeyond, session 24), the run
  // without the option enters that half too (100 %), so only the run with it is checked here.
  const sim::World world = FloorPlanRooms();
  ExplorerOptions options;
  options.doorway_goals = false;  // with it the robot enters that room facing its east half
  const kernel::OptionsOf<RegOptions> look(RegOptions{.look_before_giving_up = true});
  const Trial t = ExploreWorld("reg", world, 1, options, false, &look);
  EXPECT_TRUE(NodeIn(t.run, {3.7, 0.3}, {5.9, 3.3}));
  EXPECT_GT(t.coverage, 0.97);
  EXPECT_EQ(t.run.termination, Termination::kExplored) << t.run.message;
}

TEST(ExplorationCauses, ACorridorBehindANodeInADoorwayIsRetriedFromAnotherNode) {
  // office-long: REG stops in a doorway facing the room; the corridor behind it is seen by the
  // sonars only, whose blind spikes close the way back, and its continuation (the whole east
  // half) is given up. Retried from the node whose LSR reaches nearest and sees it (retry_nodes),
  // facing it, the floor is explored. Measured without retries (the other options on): seed 4
  // 52.9 %, seed 7 45.7 % (seeds 1 and 9 showed it before the union-walk fix of session 24, and
  // no longer do).
  ExplorerOptions no_retries;
  no_retries.retry_nodes = 0;
  for (const std::uint64_t seed : {4, 7}) {
    const Trial before = Explore("reg", "office-long", seed, no_retries);
    EXPECT_LT(before.coverage, 0.6) << "seed " << seed;
    EXPECT_EQ(before.run.termination, Termination::kIncomplete) << before.run.message;
    EXPECT_FALSE(NodeIn(before.run, {20.3, 7.3}, {24.7, 11.7})) << "seed " << seed;
    const Trial t = Explore("reg", "office-long", seed);
    EXPECT_GT(t.coverage, 0.98) << "seed " << seed;
    EXPECT_TRUE(NodeIn(t.run, {20.3, 7.3}, {24.7, 11.7})) << "seed " << seed;  // a far room
  }
}

TEST(ExplorationCauses, ARoomBesideANodeAtTheSonarsBoundaryIsEntered) {
  // office, seed 7: REG's node below the middle south room's table stands 0.267 m from the sonars'
  // boundary, 5 cm nearer than its disc needs; the grid's way out came 2-4 mm closer still, every
  // path failed the exact test, and the room's east part (x 8-10, south of the table) was given
  // up. Leaving by an exactly checked straight leg (exact_escapes), REG enters it. Since the
  // union-walk fix of session 24 the run without the option (and without doorway_goals) enters
  // it too (99.3 %); the escapes' own test is
  // Session.PropertyARobotBesideTheSonarsBoundaryLeavesByAnExactLeg.
  ExplorerOptions with;
  with.doorway_goals = false;
  EXPECT_GT(Explore("reg", "office", 7, with).coverage, 0.98);
  EXPECT_GT(Explore("reg", "office", 7).coverage, 0.98);  // the defaults
}

TEST(ExplorationCauses, ARoomWhoseDoorWasSeenOnlyAtASlantIsEntered) {
  // SRT in office, seed 1: the corridor nodes saw the north-east room only through its door at a
  // slant, in a wedge narrower than the robot; the approach to the point nearest the arc stopped
  // beside the door and looked past it again, and the room was left (86.9 %). Approached on the
  // door's axis, facing through it (doorway_goals), SRT enters it. Since the union-walk fix of
  // session 24 SRT enters it without the option too (99.1 %); the approach's own test is
  // Session.ADoorSeenAtASlantNearTheRimIsAFrontierASlitIsNot.
  const Trial t = Explore("srt", "office", 1);
  EXPECT_GT(t.coverage, 0.98);
  EXPECT_TRUE(NodeIn(t.run, {11.3, 7.3}, {15.7, 11.7}));
}

TEST(ExplorationCauses, PropertyARobotInADoorwayLooksBeforeItGivesUp) {
  // office, REG with ekf-lines, seed 5 (91.2 %): a node stopped in a doorway 0.15 m north of the
  // wall, facing south-west. Its laser's 240 deg end at -35 deg, so it saw the room through the
  // door in a wedge whose apex, at the robot, was too narrow for its disc: no path led in, and
  // the room was given up. The same kind of start here, in the 0.9 m door of CorridorAndRoom at
  // 42 poses (2 x 3 positions, 7 headings): turning to face a piece that no leg reaches and
  // sensing again (look_before_giving_up, off by default) opens the wedge. Measured without it
  // before the union-walk fix of session 24: 5 of the 42 ended incomplete at 53-87 %, two without
  // entering the room; since that fix none does, with or without it, and both are checked.
  // Without doorway_goals, as before (with it and min_doorway_arc_m at 0, two starts ended
  // `incomplete` at 99-100 % for a one-beam arc past the corridor's end corner).
  sim::World w = CorridorAndRoom();
  ExplorerOptions options;
  options.doorway_goals = false;
  for (const double x : {5.95, 6.05}) {
    for (const double y : {0.1, 0.25, 0.4}) {
      for (const double heading : {-2.7, 3.14, 2.0, 1.57, 0.5, 0.0, -0.4}) {
        w.start = kernel::Pose2(x, y, heading);
        for (const bool look : {false, true}) {
          const kernel::OptionsOf<RegOptions> reg(RegOptions{.look_before_giving_up = look});
          const Trial t = ExploreWorld("reg", w, 1, options, false, &reg);
          EXPECT_EQ(t.run.termination, Termination::kExplored) << t.run.message;
          EXPECT_GT(t.coverage, 0.98) << x << " " << y << " " << heading;
          EXPECT_TRUE(NodeIn(t.run, {4.3, -6.2}, {7.7, -0.5}))
              << x << " " << y << " " << heading << " look " << look;
        }
      }
    }
  }
}

TEST(ExplorationCauses, TheFloorBehindATableIsSeen) {
  // A 6 m x 5 m room with a 3 m table across it, 1.5 m from the south wall: from the start in the
  // north nothing reaches r = 3 m beyond the table, so the floor behind it is no free arc, only a
  // shadow (ExplorerOptions::shadow_frontiers). Since the union-walk fix of session 24, REG
  // without shadows (and without unseen stretches and door arcs) gets behind it too (99.96,
  // 99.68, 99.88 %), so only the defaults are checked.
  sim::World w;
  w.name = "room-with-table";
  using V = Eigen::Vector2d;
  w.obstacles.push_back(sim::Polyline{{V(0, 0), V(6, 0), V(6, 5), V(0, 5), V(0, 0)}, false});
  w.obstacles.push_back(sim::Polyline{{V(1.5, 1.5), V(4.5, 1.5), V(4.5, 2.3), V(1.5, 2.3)}, true});
  w.start = kernel::Pose2(3.0, 3.8, -kernel::kPi / 2);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Trial t = ExploreWorld("reg", w, seed);
    EXPECT_GT(t.coverage, 0.98) << "seed " << seed;
    EXPECT_TRUE(NodeIn(t.run, {0.3, 0.3}, {5.7, 1.5})) << "seed " << seed;
  }
}

TEST(Exploration, RegExploresComplexAndReturnsHome) {
  const Trial t = Explore("reg", "complex", 1);
  EXPECT_EQ(t.run.termination, Termination::kExplored) << t.run.message;
  EXPECT_GT(t.coverage, 0.97);
  EXPECT_EQ(t.run.blocked_steps, 0);
  // Back at the start, and the structure is a graph (edges through overlaps), not a tree.
  EXPECT_LT(
      (t.run.trace.back().truth.translation() - t.run.trace.front().truth.translation()).norm(),
      0.1);
  EXPECT_GT(t.run.graph.num_edges(), t.run.graph.num_nodes() - 1);
  EXPECT_GT(t.run.graph.num_nodes(), 20u);
  EXPECT_LT(t.run.graph.num_nodes(), 60u);
  // No open frontier is left behind.
  for (graph::Vertex v = 0; v < t.run.graph.num_nodes(); ++v)
    EXPECT_TRUE(t.run.graph[v].frontiers.empty()) << "node " << v;
}

TEST(Exploration, SrtBuildsATreeAndEndsAtTheRoot) {
  const Trial t = Explore("srt", "complex", 1);
  EXPECT_EQ(t.run.termination, Termination::kExplored) << t.run.message;
  EXPECT_GT(t.coverage, 0.99);
  EXPECT_EQ(t.run.graph.num_edges(), t.run.graph.num_nodes() - 1);
  EXPECT_LT(
      (t.run.trace.back().truth.translation() - t.run.trace.front().truth.translation()).norm(),
      0.1);
  for (const GivenUpFrontier& f : t.run.given_up) EXPECT_FALSE(f.open) << "node " << f.node;
}

TEST(Exploration, PublishedSrtKeepsValidConfAndReportsWhatItLeftOpen) {
  ExplorerOptions options;  // SRT as published: free arcs only, VALID_CONF never relaxed, no
  options.shadow_frontiers = false;  // retries
  options.retry_nodes = 0;
  options.unseen_frontiers = false;
  const kernel::OptionsOf<SrtOptions> published(SrtOptions{.relaxed_valid_conf = false});
  const Trial t = Explore("srt", "office", 2, options, false, &published);
  // VALID_CONF: no node lies inside the LSR of another (up to the goal tolerance).
  const auto& g = t.run.graph;
  for (graph::Vertex a = 0; a < g.num_nodes(); ++a) {
    for (graph::Vertex b = 0; b < g.num_nodes(); ++b) {
      if (a == b || t.run.nodes[b].parent != static_cast<int>(a)) continue;
      for (graph::Vertex c = 0; c < b; ++c) {
        if (c != a) {
          EXPECT_FALSE(
              g[c].lsr.Contains(g[b].configuration.translation() + Eigen::Vector2d(0.06, 0.0)) &&
              g[c].lsr.Contains(g[b].configuration.translation() - Eigen::Vector2d(0.06, 0.0)))
              << "node " << b << " inside node " << c;
        }
      }
    }
  }
  // Its draws ran out at nodes whose free arcs no LSR saw beyond (rooms seen through their doors
  // only: 49 % covered, 75 % since the union-walk fix of session 24): the run is incomplete and
  // says where.
  EXPECT_LT(t.coverage, 0.8);
  EXPECT_EQ(t.run.termination, Termination::kIncomplete) << t.run.message;
  int open = 0;
  for (const GivenUpFrontier& f : t.run.given_up) {
    if (!f.open) continue;
    ++open;
    const kernel::Box2 bounds = sim::BuiltinWorld("office")->Bounds();
    EXPECT_TRUE((f.midpoint.array() >= bounds.min.array()).all() &&
                (f.midpoint.array() <= bounds.max.array()).all());
    EXPECT_NE(f.reason.find("draws"), std::string::npos);
  }
  EXPECT_GE(open, 1);
}

TEST(Exploration, CapsStopWithAStatedReason) {
  ExplorerOptions options;
  options.max_nodes = 5;
  const Trial nodes = Explore("reg", "complex", 2, options);
  EXPECT_EQ(nodes.run.termination, Termination::kNodeLimit);
  EXPECT_EQ(nodes.run.graph.num_nodes(), 5u);
  options = {};
  options.max_time_s = 60.0;
  const Trial time = Explore("srt", "office", 2, options);
  EXPECT_EQ(time.run.termination, Termination::kTimeLimit);
  EXPECT_LT(time.run.time_s, 60.0 + 60.0);  // the move under way when the cap hit may finish
  options = {};
  options.alpha = 0.95;  // no room for the robot inside the LSR
  const Trial bad = Explore("reg", "complex", 2, options);
  EXPECT_EQ(bad.run.termination, Termination::kInvalidInput);
  EXPECT_NE(bad.run.message.find("alpha"), std::string::npos);
}

TEST(Exploration, OdometryLocalisationTerminatesWithoutCollisions) {
  // The explorer plans on drifting dead reckoning; the simulator refuses colliding steps and
  // the explorer must carry on or stop with a reason, never loop.
  const Trial t = Explore("reg", "office", 3, {}, /*odometry=*/true);
  EXPECT_NE(t.run.termination, Termination::kInvalidInput);
  EXPECT_GT(t.run.time_s, 60.0);
  EXPECT_GT(t.coverage, 0.3);
}

// REG's and SRT's run loops ask their steps; a variant overrides one. Overrides that count their
// calls and defer to the base give the same run to the bit, so the loop calls exactly the steps
// it names; an override that changes a step changes the run.
class CountingReg : public RegExplorer {
 public:
  using RegExplorer::RegExplorer;
  kernel::FrontierArc NextPiece(Session& session, graph::Vertex node,
                                std::vector<kernel::FrontierArc>* frontiers,
                                double max_piece_rad) override {
    ++pieces;
    if (last_arc) return TakePiece(session, frontiers, frontiers->size() - 1, max_piece_rad);
    return RegExplorer::NextPiece(session, node, frontiers, max_piece_rad);
  }
  std::optional<graph::GraphPath> NextNode(Session& session, graph::Vertex current,
                                           const std::vector<graph::Vertex>& targets) override {
    ++next_nodes;
    return RegExplorer::NextNode(session, current, targets);
  }
  bool last_arc = false;
  int pieces = 0, next_nodes = 0;
};
class CountingSrt : public SrtExplorer {
 public:
  using SrtExplorer::SrtExplorer;
  double NextDirection(Session& session, graph::Vertex node,
                       const std::vector<kernel::FrontierArc>& frontiers) override {
    ++directions;
    return SrtExplorer::NextDirection(session, node, frontiers);
  }
  int BacktrackTo(Session& session, graph::Vertex node) override {
    ++backtracks;
    return SrtExplorer::BacktrackTo(session, node);
  }
  int directions = 0, backtracks = 0;
};

ExplorationRun RunIn(Explorer* explorer, const sim::World& world) {
  const sim::RayCaster caster(world);
  sim::SimulatorOptions sim_options;
  sim_options.enable_sonar = true;
  sim::Simulator simulator(caster, sim_options, *world.start, 3);
  runtime::SimulatedRobot robot(&simulator);
  GroundTruthLocalization truth;
  return explorer->Run(&robot, &truth);
}

TEST(ExplorerSteps, TheRunLoopsAskTheirStepsAndAVariantOverridesOne) {
  const sim::World world = *sim::BuiltinWorld("office");
  ExplorerOptions options;
  options.seed = 3;
  RegExplorer reg(options);
  CountingReg counting(options), last(options);
  last.last_arc = true;
  const ExplorationRun a = RunIn(&reg, world), b = RunIn(&counting, world), c = RunIn(&last, world);
  EXPECT_GT(counting.pieces, 10);
  EXPECT_GT(counting.next_nodes, 0);
  EXPECT_EQ(a.graph.num_nodes(), b.graph.num_nodes());
  EXPECT_EQ(a.distance_m, b.distance_m);
  EXPECT_NE(a.distance_m, c.distance_m);

  SrtExplorer srt(options);
  CountingSrt counting_srt(options);
  const ExplorationRun s = RunIn(&srt, world), t = RunIn(&counting_srt, world);
  EXPECT_GT(counting_srt.directions, 10);
  EXPECT_GT(counting_srt.backtracks, 0);
  EXPECT_EQ(s.graph.num_nodes(), t.graph.num_nodes());
  EXPECT_EQ(s.distance_m, t.distance_m);
}

}  // namespace
}  // namespace splam::exploration
