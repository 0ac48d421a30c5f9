// The named steps of SRT and REG on small hand-made LSRs.
#include "exploration/steps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "exploration/active_loop_closing.h"
#include "exploration/localization.h"
#include "graph/frontiers.h"
#include "kernel/angle.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"

namespace splam::exploration {
namespace {

using kernel::kPi;
using kernel::Pose2;

// A robot that never moves: only its description matters to the steps.
class StillRobot : public RobotInterface {
 public:
  const RobotDescription& description() const override { return description_; }
  bool Step(double, double) override { return false; }
  Perception ReadOdometry() override { return {}; }
  Perception Sense() override { return {}; }

 private:
  RobotDescription description_;  // radius 0.267 m
};

// A full-circle scan (1 deg beams) that sees nothing within `free_m`, except where `wall`
// returns a range.
kernel::Scan Circle(const std::function<double(double)>& range_at) {
  kernel::Scan scan;
  scan.start_angle_rad = -kPi;
  scan.angular_step_rad = kernel::DegToRad(1.0);
  scan.min_range_m = 0.02;
  scan.max_range_m = 10.0;
  for (int i = 0; i < 360; ++i) scan.ranges_m.push_back(range_at(scan.BeamAngle(i)));
  return scan;
}
kernel::Scan Open() {
  return Circle([](double) { return kernel::Scan::kNoReturn; });
}

struct Fixture {
  explicit Fixture(const ExplorerOptions& o = {}) : options(o) {}
  StillRobot robot;
  GroundTruthLocalization localization;
  ExplorerOptions options;  // r = 3 m, alpha = 0.8
  Session session{"reg", options, &robot, &localization};
  graph::ExplorationGraph& g = session.graph();
  // A node at `at` whose LSR comes from `scan` and whose frontiers are its free arcs.
  graph::Vertex Node(const Eigen::Vector2d& at, const kernel::Scan& scan, double heading = 0.0) {
    const graph::Vertex v = g.AddNode(Pose2(at, heading));
    g[v].lsr = kernel::LocalSafeRegion::FromScan(scan, Pose2(at, heading), options.lsr_radius_m);
    g[v].frontiers = session.rules().LongEnough(g[v].lsr.frontiers());
    return v;
  }
};

double Width(const std::vector<kernel::FrontierArc>& arcs) {
  double w = 0.0;
  for (const auto& a : arcs) w += a.AngularWidth();
  return w;
}
bool Covers(const std::vector<kernel::FrontierArc>& arcs, double angle) {
  for (const auto& a : arcs) {
    for (const double turn : {-2 * kPi, 0.0, 2 * kPi})
      if (angle + turn >= a.start_angle_rad && angle + turn <= a.end_angle_rad) return true;
  }
  return false;
}

TEST(CurrIntersection, RemovesTheOverlapOfTwoOpenNodesAndJoinsThem) {
  Fixture f;
  const graph::Vertex a = f.Node({0, 0}, Open()), b = f.Node({2.4, 0}, Open());
  ASSERT_NEAR(Width(f.g[a].frontiers), 2 * kPi, 0.05);
  CurrIntersection(f.session, &f.g, b);
  // The part of a's circle inside b's disc: |angle| < acos(d / 2r) = acos(0.4), and b's mirror.
  const double half = std::acos(2.4 / 6.0);
  for (const graph::Vertex v : {a, b}) {
    EXPECT_NEAR(Width(f.g[v].frontiers), 2 * kPi - 2 * half, 0.08) << v;
  }
  EXPECT_FALSE(Covers(f.g[a].frontiers, 0.0));  // towards b
  EXPECT_TRUE(Covers(f.g[a].frontiers, kPi));   // away from b
  EXPECT_FALSE(Covers(f.g[b].frontiers, kPi));
  EXPECT_TRUE(f.g.HasEdge(a, b));
}

TEST(CurrIntersection, LeavesDistantNodesAlone) {
  Fixture f;
  const graph::Vertex a = f.Node({0, 0}, Open()), b = f.Node({6.5, 0}, Open());
  CurrIntersection(f.session, &f.g, b);
  EXPECT_NEAR(Width(f.g[a].frontiers), 2 * kPi, 0.05);
  EXPECT_FALSE(f.g.HasEdge(a, b));
}

TEST(SafePath, NeedsAClearWayThroughTheOverlap) {
  Fixture f;
  // A wall at x = 1.2 between the nodes, seen by both: the LSRs still touch around its ends
  // only far from the segment, so no waypoint near a-b is clear.
  const auto wall_from = [](double x0) {
    return Circle([x0](double angle) {
      const double c = std::cos(angle);
      return std::abs(c) > 1e-9 && (x0 / c) > 0 ? x0 / c : kernel::Scan::kNoReturn;
    });
  };
  const graph::Vertex a = f.Node({0, 0}, wall_from(1.2)), b = f.Node({2.4, 0}, wall_from(-1.2));
  EXPECT_FALSE(SafePath(f.session, f.g, a, b));
  const graph::Vertex c = f.Node({0, 5}, Open()), d = f.Node({2.0, 5}, Open());
  const auto path = SafePath(f.session, f.g, c, d);
  ASSERT_TRUE(path);
  ASSERT_EQ(path->size(), 3u);
  EXPECT_NEAR(((*path)[1] - Eigen::Vector2d(1.0, 5)).norm(), 0.0, 1e-9);  // the midpoint first
}

TEST(FrontRand, TakesALeadingPieceAndKeepsTheRest) {
  Fixture f;
  kernel::Random random(7);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<kernel::FrontierArc> frontiers = {{0.0, 2.0}, {3.0, 3.5}};
    const double before = Width(frontiers);
    const kernel::FrontierArc piece = FrontRand(f.session, &frontiers, &random, 1.0);
    EXPECT_LE(piece.AngularWidth(), 1.0 + 1e-12);
    // The piece starts an arc, and what is left of it is kept (0.5 rad arcs at r = 3 m are
    // long enough to stay frontiers).
    EXPECT_TRUE(piece.start_angle_rad == 0.0 || piece.start_angle_rad == 3.0);
    EXPECT_NEAR(Width(frontiers) + piece.AngularWidth(), before, 1e-12);
  }
}

TEST(Displacement, StepsAlphaRTowardsThePieceOrAroundAnObstacle) {
  Fixture f;
  const graph::Vertex a = f.Node({0, 0}, Open());
  const auto straight = Displacement(f.session, f.g[a], {kPi / 2 - 0.3, kPi / 2 + 0.3});
  ASSERT_TRUE(straight);
  EXPECT_NEAR((straight->back() - Eigen::Vector2d(0, 2.4)).norm(), 0.0, 1e-9);
  // A pillar 1 m north: the step goes beside it, still inside the piece.
  const graph::Vertex b =
      f.Node({10, 0}, Circle([](double angle) {
               return std::abs(angle - kPi / 2) < 0.2 ? 1.0 : kernel::Scan::kNoReturn;
             }));
  const auto around = Displacement(f.session, f.g[b], {kPi / 2 - 0.6, kPi / 2 + 0.6});
  ASSERT_TRUE(around);
  const Eigen::Vector2d q = around->back() - Eigen::Vector2d(10, 0);
  const double bearing = std::atan2(q.y(), q.x());
  EXPECT_GT(std::abs(bearing - kPi / 2), 0.2);
  EXPECT_LE(std::abs(bearing - kPi / 2), 0.6 + 1e-9);
  // Walled in on every side within 0.5 m: nowhere to go.
  const graph::Vertex c = f.Node({20, 0}, Circle([](double) { return 0.5; }));
  EXPECT_FALSE(Displacement(f.session, f.g[c], {0.0, 1.0}));
}

TEST(Verifies, ThePartOfAPieceANewNodeSeesIsCovered) {
  Fixture f;
  const graph::Vertex a = f.Node({0, 0}, Open()), b = f.Node({0, 2.4}, Open());
  const kernel::FrontierArc piece{kPi / 2 - 0.5, kPi / 2 + 0.5};
  // The new node 2.4 m along the piece's midpoint covers all of it (its disc reaches
  // acos(0.4) = 1.16 rad either side).
  EXPECT_TRUE(f.session.rules().UncoveredParts(f.g[a].lsr, piece, {&f.g[b].lsr}).empty());
  const kernel::FrontierArc wide{kPi / 2 - 1.5, kPi / 2 + 1.5};
  const auto rest = f.session.rules().UncoveredParts(f.g[a].lsr, wide, {&f.g[b].lsr});
  ASSERT_EQ(rest.size(), 2u);  // both ends go back to the node
  EXPECT_NEAR(Width(rest), 3.0 - 2 * std::acos(0.4), 0.05);
}

TEST(RandomDirection, IsUniformOverTheUnionOfArcs) {
  kernel::Random random(11);
  const std::vector<kernel::FrontierArc> arcs = {{0.0, 0.5}, {2.0, 3.5}};
  int in_first = 0;
  constexpr int kDraws = 20000;
  for (int i = 0; i < kDraws; ++i) {
    const double theta = RandomDirection(arcs, &random);
    ASSERT_TRUE(Covers(arcs, theta)) << theta;
    in_first += theta <= 0.5;
  }
  EXPECT_NEAR(static_cast<double>(in_first) / kDraws, 0.25, 0.01);  // 0.5 of 2 rad
}

TEST(ValidConf, RefusesCandidatesInsideOtherNodesLsrs) {
  Fixture f;
  const graph::Vertex a = f.Node({0, 0}, Open());
  const graph::Vertex b = f.Node({2.4, 0}, Open());
  EXPECT_FALSE(OutsideOtherLsrs(f.g, b, {1.0, 0.0}));  // inside a's LSR
  EXPECT_TRUE(OutsideOtherLsrs(f.g, b, {4.0, 0.0}));   // beyond a's radius
  EXPECT_TRUE(OutsideOtherLsrs(f.g, a, {-1.0, 0.0}));  // a's own LSR does not count
  EXPECT_FALSE(OutsideOtherLsrs(f.g, a, {1.0, 0.0}));  // b's does
}

TEST(Session, LegsKeepTheRobotsRadiusFromTheLsrBoundary) {
  Fixture f;
  // A wall 1 m north of the node: legs along it must stay radius + margin (0.317 m) away.
  const graph::Vertex a = f.Node({0, 0}, Circle([](double angle) {
                                   const double s = std::sin(angle);
                                   return s > 1e-9 ? 1.0 / s : kernel::Scan::kNoReturn;
                                 }));
  const kernel::LocalSafeRegion& lsr = f.g[a].lsr;
  EXPECT_TRUE(f.session.paths().LegIsClear(lsr, {0, 0}, {2.0, 0.5}));   // 0.5 m from the wall
  EXPECT_FALSE(f.session.paths().LegIsClear(lsr, {0, 0}, {2.0, 0.8}));  // 0.2 m from the wall
  EXPECT_FALSE(f.session.paths().LegIsClear(lsr, {0, 0}, {0.0, 2.0}));  // through it
  // A goal behind a corner of the free space is reached through one waypoint, a goal beyond the
  // wall not at all.
  const auto direct = f.session.paths().PathInside(lsr, {0, 0}, {2.0, 0.3});
  ASSERT_TRUE(direct);
  EXPECT_EQ(direct->size(), 1u);
  EXPECT_FALSE(f.session.paths().PathInside(lsr, {0, 0}, {0.0, 1.5}));
}

// A robot that stopped 0.27 m in front of the sonars' boundary (the blind spikes between their
// cones) with a wall beside it, as REG's node in `office`, seed 7, below the middle room's table:
// the grid's cells out of such a start came a few millimetres closer to the boundary than the
// robot stood, every path failed the exact test, and the east of the room was given up. With
// exact_escapes the robot leaves by a straight leg the exact test passed: every goal in the open
// space ahead is reached, by legs that all pass the exact test.
TEST(Session, PropertyARobotBesideTheSonarsBoundaryLeavesByAnExactLeg) {
  kernel::Random random(18);
  int unreached_without = 0, goals = 0;
  for (int trial = 0; trial < 100; ++trial) {
    // Behind the laser's 240 deg the sonars' echoes at 0.267 m, broken by spikes out to 2 m
    // between their cones; ahead, open space. Goals to the side, where the shortest way leaves
    // the start obliquely.
    const double phase = random.Uniform(0.0, 15.0);
    const kernel::Scan scan = Circle([&](double angle) {
      if (std::abs(angle) <= kernel::DegToRad(120.0)) return kernel::Scan::kNoReturn;
      return std::fmod(kernel::RadToDeg(angle + kPi) + phase, 15.0) < 3.0 ? 2.0 : 0.267;
    });
    const double heading = random.Uniform(-kPi, kPi);
    std::vector<Eigen::Vector2d> targets;
    for (int k = 0; k < 8; ++k) {
      const double side = random.Uniform() < 0.5 ? 1.0 : -1.0;
      const double bearing = heading + side * random.Uniform(0.7, 1.7);
      const double range = random.Uniform(1.2, 2.5);
      targets.emplace_back(range * std::cos(bearing), range * std::sin(bearing));
    }
    // Anywhere within a grid cell: the raster's error depends on it.
    const Eigen::Vector2d at(random.Uniform(0.0, 0.05), random.Uniform(0.0, 0.05));
    for (const bool escapes : {false, true}) {
      ExplorerOptions options;
      options.exact_escapes = escapes;
      Fixture f(options);
      const graph::Vertex v = f.Node(at, scan, heading);
      const kernel::LocalSafeRegion& lsr = f.g[v].lsr;
      const double needed = f.session.paths().Needed();
      const double start = kernel::SegmentClearance(lsr, at, at);
      ASSERT_LT(start, needed);
      for (const Eigen::Vector2d& offset : targets) {
        const Eigen::Vector2d target = at + offset;
        if (!lsr.Contains(target) || kernel::SegmentClearance(lsr, target, target) < needed + 0.1)
          continue;
        goals += escapes;
        const auto path = f.session.paths().PathInside(lsr, at, target);
        if (!escapes) {
          unreached_without += !path;
          continue;
        }
        ASSERT_TRUE(path) << "trial " << trial << ", target " << target.transpose();
        // Each leg passes the exact test (near the start: not closer than its beginning, less
        // kStartTolerance), or, the raster's one-cell fallback, keeps a cell less than asked.
        Eigen::Vector2d from = at;
        for (const Eigen::Vector2d& next : *path) {
          const bool near_start = (from - at).norm() <= needed;
          const double asked = near_start ? start : needed;
          EXPECT_TRUE(f.session.paths().LegIsClear(lsr, from, next, near_start) ||
                      kernel::SegmentClearance(lsr, from, next) >= asked - LsrPlanner::kCellM)
              << "trial " << trial << ": leg " << from.transpose() << " -> " << next.transpose();
          from = next;
        }
      }
    }
  }
  EXPECT_GT(goals, 100);
  // The cause: without the escapes some of these goals are out of reach.
  EXPECT_GT(unreached_without, 0);
}

// A wall 1.2 m north of the node with a gap at x 1.9 to 1.9 + `gap_m`, seen at a slant near the
// LSR's rim: the room beyond shows as a free arc shorter than the gap (0.7 m: a 0.39 m arc).
kernel::Scan WallWithGap(double gap_m) {
  return Circle([gap_m](double angle) {
    const double s = std::sin(angle);
    if (s <= 1e-9) return kernel::Scan::kNoReturn;
    const double x = 1.2 * std::cos(angle) / s;
    return x >= 1.9 && x <= 1.9 + gap_m ? kernel::Scan::kNoReturn : 1.2 / s;
  });
}

// The arcs of `arcs` whose middle lies within 1 deg of `bearing`.
int ArcsAt(const std::vector<kernel::FrontierArc>& arcs, double bearing) {
  return static_cast<int>(std::count_if(arcs.begin(), arcs.end(), [&](const auto& a) {
    return a.start_angle_rad - 0.02 <= bearing && bearing <= a.end_angle_rad + 0.02;
  }));
}

// The node's LSR (r = 3 m) of WallWithGap(0.7), and the explorer's options with doorway_goals.
kernel::LocalSafeRegion DoorAtASlant() {
  return kernel::LocalSafeRegion::FromScan(WallWithGap(0.7), Pose2(0, 0, 0), 3.0);
}
ExplorerOptions DoorwayGoals(bool on) {
  ExplorerOptions options;
  options.doorway_goals = on;
  return options;
}

TEST(Session, ADoorSeenAtASlantNearTheRimIsAFrontierASlitIsNot) {
  const double door_bearing = std::atan2(1.2, 2.25);  // the 0.7 m door's middle
  for (const bool doorway_goals : {false, true}) {
    Fixture f(DoorwayGoals(doorway_goals));
    const kernel::LocalSafeRegion door = DoorAtASlant();
    // The arc is under min_frontier_m (0.5 m), the gap between its jambs is not.
    int short_arcs = 0;
    for (const auto& arc : door.frontiers()) {
      if (ArcsAt({arc}, door_bearing) == 0) continue;
      ++short_arcs;
      EXPECT_LT(graph::ArcLength(arc, 3.0), 0.5);
      const auto gap = f.session.rules().GapOf(door, arc);
      ASSERT_TRUE(gap);
      // The jambs are the first hits beside the door: along a wall at 25 deg to the beams, up to
      // a beam's footprint (1 deg at 2.9 m, 0.12 m along the wall) beyond it.
      EXPECT_GE(gap->Width(), 0.7 - 0.06);
      EXPECT_LE(gap->Width(), 0.7 + 0.18);
      EXPECT_NEAR(gap->left.y(), 1.2, 1e-6);
      EXPECT_NEAR(gap->right.y(), 1.2, 1e-6);
      // The approach stands on the door's axis, 0.3 m beyond the robot's need in front of it,
      // and faces the door's middle.
      const auto move = f.session.paths().DoorwayApproach(f.session.rules(), door, {0, 0}, arc, {});
      ASSERT_EQ(move.has_value(), doorway_goals);
      if (!move) continue;
      ASSERT_TRUE(move->face);
      EXPECT_NEAR(move->face->x(), 2.25, 0.1);
      EXPECT_NEAR(move->face->y(), 1.2, 1e-6);
      EXPECT_NEAR(move->path.back().x(), move->face->x(), 1e-9);
      EXPECT_NEAR(move->path.back().y(), 1.2 - f.session.paths().Needed() - 0.3, 1e-9);
    }
    EXPECT_EQ(short_arcs, 1);
    EXPECT_EQ(ArcsAt(f.session.rules().FrontiersOf(door), door_bearing), doorway_goals ? 1 : 0);
    // Only as the laser saw it: between two sonar cones a short arc is an artefact of the cone
    // model (the 240 deg of a laser facing away from the door leave it to the sonars).
    const kernel::FrontierArc facing_away{door_bearing + 1.0, door_bearing + 1.0 + 4 * kPi / 3};
    const kernel::FrontierArc facing{door_bearing - 2 * kPi / 3, door_bearing + 2 * kPi / 3};
    EXPECT_EQ(ArcsAt(f.session.rules().FrontiersOf(door, facing_away), door_bearing), 0);
    EXPECT_EQ(ArcsAt(f.session.rules().FrontiersOf(door, facing), door_bearing),
              doorway_goals ? 1 : 0);
    // A 0.3 m slit is no frontier either way: the robot needs 2 x 0.317 m.
    const kernel::LocalSafeRegion slit =
        kernel::LocalSafeRegion::FromScan(WallWithGap(0.3), Pose2(0, 0, 0), 3.0);
    EXPECT_EQ(ArcsAt(f.session.rules().FrontiersOf(slit), std::atan2(1.2, 2.05)), 0);
    // One or two beams free past a wall (a junction, range noise at the rim) are no door:
    // min_doorway_arc_m. The door's arc (0.39 m) is far above it; raised above the arc, it goes.
    ExplorerOptions strict = DoorwayGoals(doorway_goals);
    strict.min_doorway_arc_m = 0.45;
    Fixture g(strict);
    EXPECT_EQ(ArcsAt(g.session.rules().FrontiersOf(door), door_bearing), 0);
  }
}

// REG in `office`, seed 8 (with ekf-bspline and graph localisation): the only node that saw the
// north middle room saw it through its door at a slant, a 0.43 m arc that FrontiersOf kept; the
// node's first overlap with another LSR, which saw nothing of that room, re-applied
// min_frontier_m to the arc (UncoveredParts), dropped it, and the room was never entered. A short
// frontier nothing covers now stays (doorway_goals); what another LSR covers of it still leaves.
TEST(Session, AShortDoorArcThatNothingCoversStaysAFrontier) {
  const double door_bearing = std::atan2(1.2, 2.25);
  // A neighbour 1 m west in the same corridor: its LSR overlaps, its wall hides the room.
  const kernel::LocalSafeRegion neighbour =
      kernel::LocalSafeRegion::FromScan(Circle([](double angle) {
                                          const double s = std::sin(angle);
                                          return s <= 1e-9 ? kernel::Scan::kNoReturn : 1.2 / s;
                                        }),
                                        Pose2(-1.0, 0, 0), 3.0);
  for (const bool doorway_goals : {false, true}) {
    Fixture f(DoorwayGoals(doorway_goals));
    const kernel::LocalSafeRegion door = DoorAtASlant();
    ASSERT_TRUE(kernel::Overlaps(door, neighbour));
    for (const kernel::FrontierArc& arc : f.session.rules().FrontiersOf(door)) {
      if (ArcsAt({arc}, door_bearing) == 0) continue;
      EXPECT_EQ(f.session.rules().UncoveredParts(door, arc, {&neighbour}).size(), 1u);
      // A region that covers part of it leaves the rest to LongEnough (the door's own: nothing).
      EXPECT_TRUE(f.session.rules().UncoveredParts(door, arc, {&door}).empty());
    }
    // Kept through the overlap with the option; without it the arc was never a frontier.
    std::vector<kernel::FrontierArc> kept;
    for (const kernel::FrontierArc& arc : f.session.rules().FrontiersOf(door))
      for (const kernel::FrontierArc& part :
           f.session.rules().UncoveredParts(door, arc, {&neighbour}))
        kept.push_back(part);
    EXPECT_EQ(ArcsAt(kept, door_bearing), doorway_goals ? 1 : 0);
  }
}

// A full-circle scan (1 deg beams) of a built-in world from `pose`, ranges beyond 10 m none.
kernel::Scan ScanOf(const std::string& world_name, const Pose2& pose) {
  const sim::RayCaster caster(*sim::BuiltinWorld(world_name));
  return Circle([&](double angle) {
    const double a = pose.theta() + angle;
    const double range =
        caster.Cast({pose.translation(), Eigen::Vector2d(std::cos(a), std::sin(a))}, 10.0).range_m;
    return std::isfinite(range) ? range : kernel::Scan::kNoReturn;
  });
}

// REG in `office-doors` (seed 3 with look_before_giving_up): two hall nodes each saw the
// north-east room through its 1 m door near the rims of their LSRs, one past the round table in
// front of it, one at a slant. Each arc through the door lay inside the other LSR, whose ray left
// across its own free arc there ("its frontier carries on"), so each covered the other's; the
// pieces left were shorter than min_frontier_m and dropped, and the room was never entered while
// the run said `explored` at 95 %. With frontiers_carry_on, a free arc carries on only where it
// is a frontier itself (min_frontier_m outside the owner's circle).
TEST(CurrIntersection, TwoNodesThatSawADoorNearTheirRimsLeaveItAFrontier) {
  const Pose2 south(13.27, 7.25, 1.54), west(11.38, 8.65, 2.52);
  // Beyond the door's wall x + y = 23.5 (from (16, 7.5) to (11.5, 12)) lies the room.
  const auto into_room = [](const graph::NodeData& node) {
    int n = 0;
    for (const kernel::FrontierArc& arc : node.frontiers) {
      const Eigen::Vector2d m = node.lsr.ArcPoint(0.5 * (arc.start_angle_rad + arc.end_angle_rad));
      n += m.x() + m.y() > 23.5 + 0.1;
    }
    return n;
  };
  for (const bool carry_on : {false, true}) {
    ExplorerOptions options;
    options.frontiers_carry_on = carry_on;
    Fixture f(options);
    const graph::Vertex a = f.Node(south.translation(), ScanOf("office-doors", south), 1.54);
    const graph::Vertex b = f.Node(west.translation(), ScanOf("office-doors", west), 2.52);
    f.g[a].frontiers = f.session.rules().FrontiersOf(f.g[a].lsr);
    f.g[b].frontiers = f.session.rules().FrontiersOf(f.g[b].lsr);
    ASSERT_EQ(into_room(f.g[a]), 1);
    ASSERT_EQ(into_room(f.g[b]), 1);
    CurrIntersection(f.session, &f.g, b);
    EXPECT_EQ(into_room(f.g[a]) + into_room(f.g[b]) > 0, carry_on) << "carry_on " << carry_on;
  }
}

TEST(Session, FrontiersShorterThanTheMinimumAreDropped) {
  Fixture f;  // min_frontier_m = 0.5 at r = 3 m: arcs narrower than 1/6 rad are slits
  const std::vector<kernel::FrontierArc> arcs = {{0.0, 0.1}, {1.0, 1.2}, {2.0, 3.0}};
  const auto kept = f.session.rules().LongEnough(arcs);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].start_angle_rad, 1.0);
  EXPECT_EQ(kept[1].start_angle_rad, 2.0);
}

// A localisation that revises the past on demand, as a pose graph does when a loop closes.
class RevisingLocalization : public GroundTruthLocalization {
 public:
  std::vector<Pose2> NodePoses() const override { return revised; }
  std::vector<Pose2> revised;
};

TEST(Session, NodesFollowTheLocalisationsRevisedPoses) {
  StillRobot robot;
  RevisingLocalization localization;
  const ExplorerOptions options;
  Session session("reg", options, &robot, &localization);
  graph::ExplorationGraph& g = session.graph();
  const kernel::Scan wall = Circle([](double angle) {
    const double s = std::sin(angle);
    return s > 1e-9 ? 1.0 / s : kernel::Scan::kNoReturn;
  });
  for (const Pose2& at : {Pose2(0, 0, 0), Pose2(2, 0, 0)}) {
    const graph::Vertex v = g.AddNode(at);
    g[v].lsr = kernel::LocalSafeRegion::FromScan(wall, at, options.lsr_radius_m);
    g[v].frontiers = session.rules().LongEnough(g[v].lsr.frontiers());
  }
  g.AddEdge(0, 1, {{0, 0}, {1, 0.5}, {2, 0}});
  const graph::NodeData before = g[1];

  session.FollowRevisedNodes();  // no revision: nothing moves
  EXPECT_EQ(g[1].configuration.translation(), before.configuration.translation());

  const Pose2 a(0.1, 0.0, 0.0), b(2.0, 0.2, 0.1);
  localization.revised = {a, b};
  session.FollowRevisedNodes();
  EXPECT_EQ(g[0].configuration.translation(), a.translation());
  EXPECT_NEAR(g[1].configuration.theta(), 0.1, 1e-12);
  // Node 1's LSR and frontiers turned and moved with it: a point 0.5 m in front of it stays
  // free, 0.5 m in front of where it is now; the point beyond its wall stays outside.
  const Pose2 moved = b * before.configuration.Inverse();
  EXPECT_NEAR((g[1].lsr.center() - b.translation()).norm(), 0.0, 1e-12);
  EXPECT_TRUE(g[1].lsr.Contains(moved * Eigen::Vector2d(2.0, 0.5)));
  EXPECT_FALSE(g[1].lsr.Contains(moved * Eigen::Vector2d(2.0, 1.5)));
  ASSERT_EQ(g[1].frontiers.size(), before.frontiers.size());
  for (std::size_t i = 0; i < before.frontiers.size(); ++i)
    EXPECT_NEAR(g[1].frontiers[i].start_angle_rad, before.frontiers[i].start_angle_rad + 0.1,
                1e-12);
  // The path joins the moved nodes; its middle point moved by the mean of the two corrections.
  const graph::EdgeData* edge = g.Edge(0, 1);
  ASSERT_NE(edge, nullptr);
  const std::vector<Eigen::Vector2d>& path = edge->path;
  EXPECT_NEAR((path.front() - a.translation()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((path.back() - b.translation()).norm(), 0.0, 1e-12);
  const Eigen::Vector2d middle =
      0.5 * (Pose2(0.1, 0, 0) * Eigen::Vector2d(1, 0.5)) + 0.5 * (moved * Eigen::Vector2d(1, 0.5));
  EXPECT_NEAR((path[1] - middle).norm(), 0.0, 1e-12);
  EXPECT_NEAR(edge->length_m, (path[1] - path[0]).norm() + (path[2] - path[1]).norm(), 1e-12);
}

TEST(ExplorationGraph, NodesEdgesAndWaypoints) {
  graph::ExplorationGraph g;
  const graph::Vertex a = g.AddNode(Pose2(0, 0, 0));
  const graph::Vertex b = g.AddNode(Pose2(2, 0, 0));
  const graph::Vertex c = g.AddNode(Pose2(2, 2, 0));
  g.AddEdge(a, b, {{0, 0}, {1, 1}, {2, 0}});
  g.AddEdge(c, b);
  EXPECT_TRUE(g.HasEdge(b, a));
  EXPECT_FALSE(g.HasEdge(a, c));
  const std::vector<Eigen::Vector2d> forward = g.Waypoints({a, b, c});
  ASSERT_EQ(forward.size(), 3u);  // (1, 1), (2, 0), (2, 2)
  EXPECT_EQ(forward[0], Eigen::Vector2d(1, 1));
  EXPECT_EQ(forward[2], Eigen::Vector2d(2, 2));
  const std::vector<Eigen::Vector2d> back = g.Waypoints({b, a});
  ASSERT_EQ(back.size(), 2u);  // the stored path reversed
  EXPECT_EQ(back[0], Eigen::Vector2d(1, 1));
  EXPECT_EQ(back[1], Eigen::Vector2d(0, 0));
}

}  // namespace
}  // namespace splam::exploration

namespace splam::exploration {
namespace {

// A localisation that says what a revisit gives: `information[v]` for node v, less `per_m`
// for every metre of the drive.
class KnownInformation : public GroundTruthLocalization {
 public:
  std::vector<double> information;
  double per_m = 0.0;
  std::vector<std::optional<double>> RevisitInformation(
      const std::vector<int>& nodes, const std::vector<double>& path_m) const override {
    std::vector<std::optional<double>> out;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      out.push_back(information[static_cast<std::size_t>(nodes[i])] - per_m * path_m[i]);
    return out;
  }
};

// A chain 0 - 1 - 2 - 3 - 4, 5 m a link, and a node 5 no edge reaches.
graph::ExplorationGraph Chain() {
  graph::ExplorationGraph g;
  for (int i = 0; i < 5; ++i) g.AddNode(kernel::Pose2(5.0 * i, 0.0, 0.0));
  for (graph::Vertex v = 1; v < 5; ++v) g.AddEdge(v - 1, v);
  g.AddNode(kernel::Pose2(0.0, 9.0, 0.0));
  return g;
}

// The revisit of highest information less cost_nats_per_m times the detour (twice the path),
// over the graph's shortest path; none where nothing gains enough, none through no edge.
TEST(ChooseRevisit, WeighsInformationAgainstTheDetour) {
  const graph::ExplorationGraph g = Chain();
  KnownInformation localization;
  localization.information = {6.0, 5.0, 1.0, 0.5, 0.0, 50.0};
  ActiveLoopClosingOptions options;
  options.cost_nats_per_m = 0.25;
  options.min_information_nats = 0.69;
  // From node 4: node 0 gives 6 - 0.25 * 40 < 0, node 1 5 - 0.25 * 30 < 0, node 2 1 - 5 < 0.
  EXPECT_FALSE(ChooseRevisit(g, 4, localization, options).has_value());
  // Cheaper metres: node 0 (6 - 0.05 * 40 = 4) beats node 1 (5 - 0.05 * 30 = 3.5) and node 5,
  // which no edge reaches; the path is the chain.
  options.cost_nats_per_m = 0.05;
  auto choice = ChooseRevisit(g, 4, localization, options);
  ASSERT_TRUE(choice.has_value());
  EXPECT_EQ(choice->to, 0u);
  EXPECT_NEAR(choice->path_m, 20.0, 1e-9);
  EXPECT_NEAR(choice->utility, 4.0, 1e-9);
  EXPECT_EQ(choice->path, (std::vector<graph::Vertex>{4, 3, 2, 1, 0}));
  // Excluded (revisited already): the next best; a minimum gain it does not reach: none.
  choice = ChooseRevisit(g, 4, localization, options, {0});
  ASSERT_TRUE(choice.has_value());
  EXPECT_EQ(choice->to, 1u);
  options.min_information_nats = 5.5;
  EXPECT_FALSE(ChooseRevisit(g, 4, localization, options, {0}).has_value());
  // A localisation that cannot say (ground truth) never revisits.
  options.min_information_nats = 0.0;
  EXPECT_FALSE(ChooseRevisit(g, 4, GroundTruthLocalization(), options).has_value());
  // The information the localisation gives depends on the path it is told.
  localization.per_m = 0.2;
  choice = ChooseRevisit(g, 4, localization, options);
  ASSERT_TRUE(choice.has_value());
  EXPECT_EQ(choice->to, 1u);  // 5 - 3 - 1.5 = 0.5 beats 6 - 4 - 2 = 0
}

TEST(PositionSigma, IsTheLargestPositionAxis) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c(0, 0) = 0.25;
  c(1, 1) = 1.0;
  c(2, 2) = 100.0;  // the heading does not count
  EXPECT_NEAR(PositionSigma(c), 1.0, 1e-12);
  c(0, 1) = c(1, 0) = 0.5;  // eigenvalues (1.25 +- sqrt(0.5625 + 1)) / 2
  EXPECT_NEAR(PositionSigma(c), std::sqrt((1.25 + std::sqrt(0.5625 + 1.0)) / 2.0), 1e-12);
}

}  // namespace
}  // namespace splam::exploration
