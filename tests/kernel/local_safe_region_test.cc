// Local safe regions: star-shaped regions from scans, their frontier arcs, exact containment.
#include "kernel/local_safe_region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

// A URG-04LX-like scan: 240 deg at 0.36 deg.
Scan UrgScan(double range) {
  Scan s;
  s.angular_step_rad = DegToRad(0.36);
  s.start_angle_rad = -DegToRad(0.36) * 333;
  s.max_range_m = 4.0;
  s.ranges_m.assign(667, range);
  return s;
}

TEST(LocalSafeRegion, OpenSpaceIsOneFrontierOverTheFieldOfView) {
  const Pose2 pose(1, 2, 0.5);
  const LocalSafeRegion lsr = LocalSafeRegion::FromScan(UrgScan(Scan::kNoReturn), pose, 2.0);
  ASSERT_EQ(lsr.frontiers().size(), 1u);
  EXPECT_NEAR(lsr.frontiers()[0].start_angle_rad, 0.5 - DegToRad(0.36) * 333, 1e-12);
  EXPECT_NEAR(lsr.frontiers()[0].AngularWidth(), DegToRad(0.36) * 666, 1e-12);
  const Eigen::Vector2d ahead(std::cos(0.5), std::sin(0.5));
  EXPECT_TRUE(lsr.Contains(pose.translation() + 1.9 * ahead));
  EXPECT_FALSE(lsr.Contains(pose.translation() + 2.1 * ahead));
  EXPECT_FALSE(lsr.Contains(pose.translation() - 0.5 * ahead));  // behind: never seen
}

TEST(LocalSafeRegion, ObstaclesSplitTheFrontier) {
  // Beams 200-299 and 500-519 hit something at 1 m: three free arcs remain.
  Scan scan = UrgScan(Scan::kNoReturn);
  for (int i = 200; i < 300; ++i) scan.ranges_m[static_cast<std::size_t>(i)] = 1.0;
  for (int i = 500; i < 520; ++i) scan.ranges_m[static_cast<std::size_t>(i)] = 1.0;
  const LocalSafeRegion lsr = LocalSafeRegion::FromScan(scan, Pose2(), 2.0);
  ASSERT_EQ(lsr.frontiers().size(), 3u);
  EXPECT_NEAR(lsr.frontiers()[0].end_angle_rad, scan.BeamAngle(199), 1e-12);
  EXPECT_NEAR(lsr.frontiers()[1].start_angle_rad, scan.BeamAngle(300), 1e-12);
  EXPECT_NEAR(lsr.frontiers()[1].end_angle_rad, scan.BeamAngle(499), 1e-12);
  EXPECT_NEAR(lsr.frontiers()[2].start_angle_rad, scan.BeamAngle(520), 1e-12);
  // Readings beyond the radius are free too; shorter ones are not.
  scan.ranges_m.assign(667, 2.5);
  EXPECT_EQ(LocalSafeRegion::FromScan(scan, Pose2(), 2.0).frontiers().size(), 1u);
  scan.ranges_m.assign(667, 1.5);
  EXPECT_TRUE(LocalSafeRegion::FromScan(scan, Pose2(), 2.0).frontiers().empty());
}

TEST(LocalSafeRegion, FullCircleArcsJoinAcrossTheSeam) {
  Scan scan;
  scan.angular_step_rad = 2.0 * kPi / 360;
  scan.start_angle_rad = -kPi;
  scan.ranges_m.assign(360, Scan::kNoReturn);
  for (std::size_t i = 100; i < 200; ++i) scan.ranges_m[i] = 0.5;
  const LocalSafeRegion lsr = LocalSafeRegion::FromScan(scan, Pose2(), 1.0);
  ASSERT_EQ(lsr.frontiers().size(), 1u);
  EXPECT_NEAR(lsr.frontiers()[0].AngularWidth(), 2.0 * kPi / 360 * 259, 1e-9);
  EXPECT_TRUE(lsr.Contains(Eigen::Vector2d(-0.9, 0.0)));  // at the seam (angle pi)
}

TEST(LocalSafeRegion, PropertyEveryBeamRayCrossesTheBoundaryAtItsClippedReading) {
  // Star-shaped: along each beam, points before the clipped reading are inside and points
  // beyond it are outside, whatever the readings (hits, no-returns, invalid) and the pose.
  Random random(71);
  for (int trial = 0; trial < 100; ++trial) {
    Scan scan = UrgScan(0.0);
    for (double& r : scan.ranges_m) {
      const double u = random.Uniform(0, 1);
      r = u < 0.05  ? std::numeric_limits<double>::quiet_NaN()
          : u < 0.3 ? Scan::kNoReturn
                    : random.Uniform(0.1, 3.5);
    }
    const Pose2 pose(random.Uniform(-5, 5), random.Uniform(-5, 5), random.Uniform(-3, 3));
    const double radius = random.Uniform(0.5, 3.0);
    const LocalSafeRegion lsr = LocalSafeRegion::FromScan(scan, pose, radius);
    for (int k = 0; k < 20; ++k) {
      const std::size_t i = 1 + random.Index(scan.size() - 2);
      const double r = scan.ranges_m[i];
      const double reach = std::isnan(r) ? 0.01 * radius : std::clamp(r, 0.01 * radius, radius);
      const double a = pose.theta() + scan.BeamAngle(i);
      const Eigen::Vector2d d(std::cos(a), std::sin(a));
      EXPECT_TRUE(lsr.Contains(pose.translation() + 0.999 * reach * d));
      EXPECT_FALSE(lsr.Contains(pose.translation() + 1.001 * reach * d));
    }
  }
}

TEST(LocalSafeRegion, OverlapNeedsASharedPoint) {
  const Scan open = UrgScan(Scan::kNoReturn);
  const LocalSafeRegion a = LocalSafeRegion::FromScan(open, Pose2(0, 0, 0), 2.0);
  EXPECT_TRUE(Overlaps(a, LocalSafeRegion::FromScan(open, Pose2(3, 0, kPi), 2.0)));
  EXPECT_FALSE(Overlaps(a, LocalSafeRegion::FromScan(open, Pose2(5, 0, kPi), 2.0)));
  // Walls at 1 m all round: two such regions 2.5 m apart do not touch, though their radii do.
  const Scan walled = UrgScan(1.0);
  const LocalSafeRegion c = LocalSafeRegion::FromScan(walled, Pose2(0, 0, 0), 2.0);
  EXPECT_FALSE(Overlaps(c, LocalSafeRegion::FromScan(walled, Pose2(2.5, 0, kPi), 2.0)));
  EXPECT_TRUE(Overlaps(c, LocalSafeRegion::FromScan(walled, Pose2(1.9, 0, kPi), 2.0)));
}

TEST(LocalSafeRegion, PropertyOverlapAgreesWithSampledCommonPoints) {
  // Whenever a sample point lies in both regions they overlap; and overlapping regions of
  // positive area share sample points on a fine enough grid (checked one way only: a grid can
  // miss a sliver).
  Random random(73);
  int overlapping = 0;
  for (int trial = 0; trial < 60; ++trial) {
    LocalSafeRegion lsr[2];
    for (LocalSafeRegion& l : lsr) {
      Scan scan = UrgScan(0.0);
      for (double& r : scan.ranges_m)
        r = random.Uniform(0, 1) < 0.4 ? Scan::kNoReturn : random.Uniform(0.3, 3.0);
      l = LocalSafeRegion::FromScan(
          scan, Pose2(random.Uniform(-2, 2), random.Uniform(-2, 2), random.Uniform(-3, 3)), 2.0);
    }
    bool common = false;
    for (double x = -4; x <= 4 && !common; x += 0.1) {
      for (double y = -4; y <= 4 && !common; y += 0.1)
        common = lsr[0].Contains({x, y}) && lsr[1].Contains({x, y});
    }
    const bool overlaps = Overlaps(lsr[0], lsr[1]);
    EXPECT_EQ(overlaps, Overlaps(lsr[1], lsr[0])) << trial;  // symmetric
    EXPECT_TRUE(overlaps || !common) << trial;
    overlapping += overlaps;
  }
  EXPECT_GT(overlapping, 10);
  EXPECT_LT(overlapping, 60);
}

TEST(LocalSafeRegion, FrontierPartInsideAnotherRegion) {
  // The frontier of an open region at the origin (r = 2) inside an open region at (2, 0) that
  // faces it: the arc points within 2 m of (2, 0), i.e. angles in [-60, 60] deg.
  const Scan open = UrgScan(Scan::kNoReturn);
  const LocalSafeRegion a = LocalSafeRegion::FromScan(open, Pose2(0, 0, 0), 2.0);
  const LocalSafeRegion b = LocalSafeRegion::FromScan(open, Pose2(2, 0, kPi), 2.0);
  ASSERT_EQ(a.frontiers().size(), 1u);
  const double spacing = DegToRad(0.5);
  const std::vector<FrontierArc> parts = ArcPartsInside(a, a.frontiers()[0], b, spacing);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(parts[0].start_angle_rad, -kPi / 3, spacing);
  EXPECT_NEAR(parts[0].end_angle_rad, kPi / 3, spacing);
  // Nothing of it lies in a region far away.
  EXPECT_TRUE(ArcPartsInside(a, a.frontiers()[0],
                             LocalSafeRegion::FromScan(open, Pose2(9, 0, 0), 2.0), spacing)
                  .empty());
}

// A full-circle scan inside a corridor |y| <= 1 (exact ranges), one beam per degree.
Scan CorridorScan() {
  Scan scan;
  scan.angular_step_rad = 2.0 * kPi / 360;
  scan.start_angle_rad = -kPi;
  scan.max_range_m = 4.0;
  for (int i = 0; i < 360; ++i) {
    const double s = std::abs(std::sin(scan.BeamAngle(static_cast<std::size_t>(i))));
    scan.ranges_m.push_back(s < 1e-9 ? Scan::kNoReturn : 1.0 / s);
  }
  return scan;
}

TEST(LocalSafeRegion, WallsAtGrazingIncidenceAreNoShadowsAnOccludersEdgesAre) {
  // Along the corridor's walls the range grows smoothly from beam to beam, up to 57 cm a beam
  // near the axis: no shadow edge.
  const LocalSafeRegion corridor = LocalSafeRegion::FromScan(CorridorScan(), Pose2(0, 0, 0), 3.0);
  EXPECT_TRUE(OcclusionEdges(corridor, 0.2, 0.0).empty());
  // A box 1 m ahead (beams within 10 deg of the axis) in open space: its two sides cast shadows.
  Scan scan = UrgScan(Scan::kNoReturn);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (std::abs(scan.BeamAngle(i)) <= DegToRad(10.0)) scan.ranges_m[i] = 1.0;
  const LocalSafeRegion box = LocalSafeRegion::FromScan(scan, Pose2(0, 0, 0), 3.0);
  const std::vector<std::size_t> shadows = OcclusionEdges(box, 0.2, 1.0);
  ASSERT_EQ(shadows.size(), 2u);
  for (const std::size_t edge : shadows) {
    const EdgeSide side = EdgeMiddleAndNormal(box, edge);
    EXPECT_NEAR(side.middle.norm(), 2.0, 0.05);        // from the box's corner to r = 3
    EXPECT_LT(std::abs(side.middle.y()), 0.4);         // beside the axis
    EXPECT_LT(side.outward.y() * side.middle.y(), 0);  // pointing behind the box
    EXPECT_TRUE(box.Contains(side.middle - 0.05 * side.outward));
    EXPECT_FALSE(box.Contains(side.middle + 0.05 * side.outward));
  }
}

TEST(LocalSafeRegion, TheUnionOfRegionsSeesBehindAShadow) {
  Scan scan = UrgScan(Scan::kNoReturn);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (std::abs(scan.BeamAngle(i)) <= DegToRad(10.0)) scan.ranges_m[i] = 1.0;
  const LocalSafeRegion box = LocalSafeRegion::FromScan(scan, Pose2(0, 0, 0), 3.0);
  // From (2, 0.6) down into the box's shadow: the ray leaves across the shadow edge after 0.25 m.
  const Eigen::Vector2d p(2.0, 0.6), down(0.0, -1.0);
  ASSERT_TRUE(box.Contains(p));
  EXPECT_FALSE(UnionSeesBeyond({&box}, p, down, {1.0, 0.2}));
  EXPECT_TRUE(UnionSeesBeyond({&box}, p, down, {0.0, 0.2}));  // the papers' rule: inside is enough
  // Towards the box the ray ends on it: seen.
  EXPECT_TRUE(UnionSeesBeyond({&box}, {0.5, 0.0}, {1.0, 0.0}, {1.0, 0.2}));
  // A second region below, looking north, sees into the shadow but not as far as p (3.1 m away):
  // the ray carries on in it where the box's region left it.
  const LocalSafeRegion below =
      LocalSafeRegion::FromScan(UrgScan(Scan::kNoReturn), Pose2(2.0, -2.5, kPi / 2), 3.0);
  ASSERT_FALSE(below.Contains(p));
  EXPECT_TRUE(UnionSeesBeyond({&box, &below}, p, down, {1.0, 0.2}));
  EXPECT_FALSE(UnionSeesBeyond({&below}, p, down, {1.0, 0.2}));
}

TEST(LocalSafeRegion, PropertyARayIntoAShadowIsNotSeenWhereNoRegionTakesItOn) {
  // Rays from random points of the box's region into its shadow, with a view depth that ends
  // before they could enter the region again: never seen. The point where a ray leaves lies on
  // the boundary, which Contains() counts as inside; the walk once took the region on again
  // there (when rounding put the crossing inside) and reported the shadow seen.
  Scan scan = UrgScan(Scan::kNoReturn);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (std::abs(scan.BeamAngle(i)) <= DegToRad(10.0)) scan.ranges_m[i] = 1.0;
  const LocalSafeRegion box = LocalSafeRegion::FromScan(scan, Pose2(0, 0, 0), 3.0);
  Random random(7);
  int trials = 0;
  for (int k = 0; k < 2000; ++k) {
    const double x = random.Uniform(1.5, 2.8);
    const double edge = x * std::tan(DegToRad(10.0));  // the shadow spans |y| < edge here
    const Eigen::Vector2d p(x, random.Uniform(edge + 0.02, edge + 0.3));
    const double angle = -kPi / 2 + random.Uniform(-0.3, 0.3);
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    if (!box.Contains(p)) continue;
    // Up to 1 cm before the shadow's far side (y = -edge): no region takes the ray on.
    const double depth = (p.y() + edge - 0.01) / -u.y();
    if (std::abs(p.x() + depth * u.x()) < 1.1 || p.x() + depth * u.x() > 2.9) continue;
    ++trials;
    EXPECT_FALSE(UnionSeesBeyond({&box}, p, u, {depth, 0.2})) << p.transpose() << " " << angle;
  }
  EXPECT_GT(trials, 1000);
}

TEST(LocalSafeRegion, LineOfSightRunsThroughTheUnionNotThroughWalls) {
  // Two corridors 2 m wide along x, one at y = 0 and one at y = 3, with a wall between them
  // (y = 1 and y = 2), and a region at x = 2.5 on the first corridor's axis that carries it on.
  const LocalSafeRegion south = LocalSafeRegion::FromScan(CorridorScan(), Pose2(0, 0, 0), 3.0);
  const LocalSafeRegion north = LocalSafeRegion::FromScan(CorridorScan(), Pose2(0, 3, 0), 3.0);
  const LocalSafeRegion east = LocalSafeRegion::FromScan(CorridorScan(), Pose2(2.5, 0, 0), 3.0);
  // Along the corridor: inside one region, then carried on across its free arc by the next.
  EXPECT_TRUE(UnionLineOfSight({&south}, {0, 0}, {2.5, 0.5}, 0.2));
  EXPECT_FALSE(UnionLineOfSight({&south}, {0, 0}, {4.5, 0.2}, 0.2));  // beyond r: unknown
  EXPECT_TRUE(UnionLineOfSight({&south, &east}, {0, 0}, {4.5, 0.2}, 0.2));
  // From one corridor to the other: through the wall, however the regions are listed.
  EXPECT_FALSE(UnionLineOfSight({&south, &north}, {0, 0.5}, {0.5, 2.5}, 0.2));
  EXPECT_FALSE(UnionLineOfSight({&north, &south, &east}, {0.5, 2.5}, {0, 0.5}, 0.2));
  // From outside every region nothing is in sight.
  EXPECT_FALSE(UnionLineOfSight({&south}, {0, 1.5}, {0, 0}, 0.2));
}

TEST(LocalSafeRegion, ClearanceOfASegmentFromTheWalls) {
  const LocalSafeRegion lsr = LocalSafeRegion::FromScan(CorridorScan(), Pose2(), 3.0);
  // Along the axis the walls are 1 m away; the boundary's chords cut in by less than 1 mm near
  // the axis and the frontier caps are 3 m away.
  EXPECT_NEAR(SegmentClearance(lsr, {0, 0}, {1.5, 0}), 1.0, 2e-3);
  EXPECT_NEAR(SegmentClearance(lsr, {0, 0}, {1.5, 0.5}), 0.5, 2e-3);
  EXPECT_EQ(SegmentClearance(lsr, {0, 0}, {0, 1.5}), 0.0);  // through the wall
  // A partial-circle region ignores its two edges at the sensor.
  const LocalSafeRegion ahead = LocalSafeRegion::FromScan(UrgScan(Scan::kNoReturn), Pose2(), 2.0);
  EXPECT_NEAR(SegmentClearance(ahead, {0, 0}, {1, 0}), 1.0, 1e-3);
}

TEST(LocalSafeRegion, PropertyClearanceIsTheDistanceToTheBoundary) {
  Random random(11);
  for (int trial = 0; trial < 100; ++trial) {
    Scan scan = UrgScan(0.0);
    scan.angular_step_rad = DegToRad(1.0);
    scan.start_angle_rad = -kPi;
    scan.ranges_m.assign(360, 0.0);
    for (double& r : scan.ranges_m) r = random.Uniform(0.5, 3.0);
    const Pose2 pose(random.Uniform(-5, 5), random.Uniform(-5, 5), random.Uniform(-kPi, kPi));
    const LocalSafeRegion lsr = LocalSafeRegion::FromScan(scan, pose, 2.0);
    const double angle = random.Uniform(-kPi, kPi);
    const Eigen::Vector2d b =
        pose.translation() +
        random.Uniform(0.1, 2.5) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    const double clearance = SegmentClearance(lsr, pose.translation(), b);
    // Brute force: points along the segment against points along the edges.
    double brute = std::numeric_limits<double>::infinity();
    const auto& pts = lsr.boundary();
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector2d& p = pts[i];
      const Eigen::Vector2d& q = pts[(i + 1) % pts.size()];
      for (int k = 0; k <= 10; ++k) {
        const Eigen::Vector2d e = p + (q - p) * k / 10.0;
        for (int j = 0; j <= 100; ++j) {
          brute = std::min(
              brute, (e - (pose.translation() + (b - pose.translation()) * j / 100.0)).norm());
        }
      }
    }
    EXPECT_LE(clearance, brute + 1e-9) << "trial " << trial;
    EXPECT_GE(clearance, brute - 0.02) << "trial " << trial;  // the sampling step
    if (!lsr.Contains(b)) {
      EXPECT_EQ(clearance, 0.0) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace splam::kernel
