#include "sim/builtin_worlds.h"

#include <gtest/gtest.h>

#include "sim/simulator.h"

namespace splam::sim {
namespace {

TEST(BuiltinWorlds, UnknownNameIsNullopt) { EXPECT_FALSE(BuiltinWorld("nowhere").has_value()); }

class BuiltinWorldTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinWorldTest, IsValidAndItsRouteIsDrivable) {
  const auto world = BuiltinWorld(GetParam());
  ASSERT_TRUE(world.has_value());
  EXPECT_EQ(world->name, GetParam());
  EXPECT_TRUE(world->Validate().ok());
  ASSERT_TRUE(world->start.has_value());
  ASSERT_FALSE(world->route.empty());
  const RayCaster caster(*world);
  Simulator sim(caster, SimulatorOptions(), *world->start, 3);
  ASSERT_TRUE(sim.IsFree(*world->start));
  const RouteRun run = FollowRoute(&sim, world->route, RouteOptions());
  EXPECT_TRUE(run.completed) << run.message;
  // The robot sees something in (almost) every scan: no scan is all no-returns.
  int blind = 0;
  for (const SensorFrame& f : run.frames) blind += f.scan.HitIndices().empty();
  EXPECT_EQ(blind, 0);
}

INSTANTIATE_TEST_SUITE_P(All, BuiltinWorldTest, ::testing::ValuesIn(BuiltinWorldNames()));

TEST(BuiltinWorlds, ComplexIsAboutTwentyByFifteenMetresWithCurves) {
  const World w = *BuiltinWorld("complex");
  const kernel::Box2 b = w.Bounds();
  EXPECT_NEAR(b.Size().x(), 21.5, 1.5);
  EXPECT_NEAR(b.Size().y(), 15.5, 1.5);
  int curved = 0;
  for (const Shape& s : w.obstacles) curved += !std::holds_alternative<Polyline>(s);
  EXPECT_GE(curved, 8);
}

TEST(BuiltinWorlds, CorridorRouteStartsTwoPointSevenDegreesOffTheAxis) {
  const World w = *BuiltinWorld("corridor");
  EXPECT_NEAR(w.start->theta(), 2.7 * M_PI / 180.0, 1e-12);
}

}  // namespace
}  // namespace splam::sim
