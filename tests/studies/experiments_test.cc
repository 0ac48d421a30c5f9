// The experiments' scoring: the corridor's distances and the wrong associations.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "estimation/map_line.h"
#include "kernel/angle.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "studies/association_scoring.h"
#include "studies/corridor_experiment.h"

namespace splam::studies {
namespace {

estimation::MapLine Wall(double rho, double theta, Eigen::Vector2d start, Eigen::Vector2d end,
                         int observations = 5) {
  estimation::MapLine l;
  l.line = {rho, theta};
  l.start = start;
  l.end = end;
  l.covariance.setIdentity();
  l.observations = observations;
  return l;
}

TEST(CorridorScoring, TrueValuesOfTheNineDistances) {
  const auto& d = CorridorDistances();
  ASSERT_EQ(d.size(), 9u);
  EXPECT_NEAR(d[0].TrueValue(), 2.4, 1e-12);  // corridor width
  EXPECT_NEAR(d[1].TrueValue(), 2.0, 1e-12);  // south room depth
  EXPECT_NEAR(d[3].TrueValue(), 2.4, 1e-12);  // corners (18, -1.2)-(18, 1.2)
  EXPECT_NEAR(d[8].TrueValue(), 4.0, 1e-12);
}

TEST(CorridorScoring, MeasuresWallsAndCornersOfAMap) {
  const double up = kernel::kPi / 2;
  // Two walls 2.5 m apart (normals pointing away from the corridor), a distractor wall 10 deg
  // off, and a better observed duplicate of the south wall 5 cm away.
  std::vector<estimation::MapLine> lines = {
      Wall(1.25, up, {0, 1.25}, {10, 1.25}),
      Wall(1.2, -up, {0, -1.2}, {10, -1.2}, 3),
      Wall(1.25, -up, {0, -1.25}, {10, -1.25}, 9),
      Wall(1.2, up + kernel::DegToRad(10), {0, 1.2}, {10, 1.2}, 50),
  };
  const CorridorDistance width = CorridorDistances()[0];
  const auto measured = MeasuredDistance(width, lines, {});
  ASSERT_TRUE(measured);
  EXPECT_NEAR(*measured, 2.5, 1e-9);                    // the most observed of the candidates
  EXPECT_EQ(MappedWall({5, 3.0}, up, lines), nullptr);  // 1.75 m away from every wall
  // Corners: a landmark within 0.25 m, else the crossing of two mapped lines.
  estimation::MapCorner c;
  c.position = Eigen::Vector2d(18.1, 1.2);
  c.covariance.setIdentity();
  const std::vector<estimation::MapLine> crossing = {Wall(18.0, 0.0, {18, -3}, {18, -1}),
                                                     Wall(1.3, -up, {15, -1.3}, {18, -1.3})};
  const auto a = MappedCorner({18, 1.2}, {c}, {});
  ASSERT_TRUE(a);
  EXPECT_NEAR((*a - Eigen::Vector2d(18.1, 1.2)).norm(), 0.0, 1e-12);
  const auto b = MappedCorner({18, -1.2}, {c}, crossing);
  ASSERT_TRUE(b);
  EXPECT_NEAR((*b - Eigen::Vector2d(18, -1.3)).norm(), 0.0, 1e-9);
  EXPECT_FALSE(MappedCorner({0, 0}, {c}, crossing));
  EXPECT_NEAR(*MeasuredDistance(CorridorDistances()[3], crossing, {c}), 2.5 + 0.0, 0.01);
}

TEST(CorridorExperiment, ShortRunsMapTheCorridorConsistently) {
  CorridorOptions options;
  options.runs = 3;
  options.steps = 60;
  const CorridorResult r = RunCorridorExperiment(options);
  ASSERT_TRUE(r.error.empty()) << r.error;
  ASSERT_EQ(r.average_nees.size(), 61u);
  EXPECT_EQ(r.final_error_m.size(), 3u);
  EXPECT_FALSE(r.measured[0].empty());  // the corridor's width is always mapped
  for (double w : r.measured[0]) EXPECT_NEAR(w, 2.4, 0.05);
  EXPECT_LT(r.final_error_m[0], r.final_odometry_error_m[0] + 0.05);
}

TEST(AssociationScoring, VotesAndMajority) {
  const std::vector<int> obstacles = {3, 3, -1, 5, 5, 5, 3};
  EXPECT_EQ(Votes({0, 1, 2, 6}, obstacles), (std::map<int, int>{{-1, 1}, {3, 3}}));
  EXPECT_EQ(MajorityObstacle({0, 3, 4, 5}, obstacles), 5);
  EXPECT_EQ(MajorityObstacle({0, 3}, obstacles), 3);  // a tie: the lowest index
  EXPECT_EQ(MajorityObstacle({}, obstacles), -1);
}

TEST(AssociationScoring, TheCurvatureAssociationIsRarelyWrongOnTheComplexRoute) {
  const sim::World world = *sim::BuiltinWorld("complex");
  const sim::RayCaster caster(world);
  sim::Simulator simulator(caster, sim::SimulatorOptions(), *world.start, 2);
  sim::RouteOptions route;
  route.max_steps = 400;
  const sim::RouteRun run = sim::FollowRoute(&simulator, world.route, route);
  const AssociationRun r =
      RunBSplineFilter(run.frames, caster, estimation::EkfBSplineSlamOptions());
  ASSERT_TRUE(r.healthy);
  EXPECT_EQ(r.estimate.size(), run.frames.size());
  EXPECT_GT(r.associations, 300);
  EXPECT_LT(r.wrong_associations, r.associations / 20);
  EXPECT_LT(r.map_error_m, 0.05);
  EXPECT_GT(r.mean_nees, 0.0);
}

}  // namespace
}  // namespace splam::studies
