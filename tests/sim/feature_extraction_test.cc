// The kernel's geometry on simulated scans of both lasers: everything extracted must lie on the
// world's obstacles, which the simulator knows exactly.
#include <gtest/gtest.h>

#include "kernel/lines.h"
#include "kernel/spline_extraction.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace splam::sim {
namespace {

struct Case {
  std::string world;
  bool lms;
};

class FeatureExtractionTest : public ::testing::TestWithParam<Case> {};

TEST_P(FeatureExtractionTest, CurvesAndLinesLieOnTheObstacles) {
  const World world = *BuiltinWorld(GetParam().world);
  const RayCaster caster(world);
  SimulatorOptions options;
  options.laser = GetParam().lms ? LaserOptions::Lms200() : LaserOptions::Urg04lx();
  Simulator simulator(caster, options, *world.start, 5);
  const RouteRun run = FollowRoute(&simulator, world.route, RouteOptions());
  ASSERT_TRUE(run.completed);
  int curves = 0, lines = 0, off_curve = 0, samples = 0, off_line = 0;
  for (std::size_t f = 0; f < run.frames.size(); f += 25) {
    const SensorFrame& frame = run.frames[f];
    const kernel::Pose2& T = frame.true_pose;  // the laser sits at the robot's origin
    for (const kernel::SplineCurve& c : kernel::ExtractCurves(frame.scan)) {
      ++curves;
      for (std::size_t i = 0; i < c.samples.size(); i += 5) {
        ++samples;
        off_curve += !caster.Collides(T * c.samples[i], 0.05);
      }
    }
    // Lines are checked in the worlds of straight walls only: on a curved wall a line is a
    // chord, off the arc by its sagitta (6 cm for a 1 m chord of a 2 m radius) and more at its
    // ends; that is what the B-splines are for.
    if (GetParam().world == "complex") continue;
    for (const kernel::LineFeature& l : kernel::ExtractLines(frame.scan).lines) {
      ++lines;
      off_line += !caster.Collides(T * l.start, 0.05) || !caster.Collides(T * l.end, 0.05) ||
                  !caster.Collides(T * (0.5 * (l.start + l.end)), 0.05);
    }
  }
  EXPECT_GT(curves, 10);
  // Curve samples within 5 cm of an obstacle; the rare exceptions are curves bridging two
  // obstacles that the segmentation joined.
  EXPECT_LT(off_curve, samples / 50) << off_curve << " of " << samples;
  if (GetParam().world != "complex") {
    EXPECT_GT(lines, 10);
    EXPECT_LT(off_line, lines / 10 + 1) << off_line << " of " << lines;
  }
}

INSTANTIATE_TEST_SUITE_P(BothLasers, FeatureExtractionTest,
                         ::testing::Values(Case{"complex", false}, Case{"complex", true},
                                           Case{"office", false}, Case{"office", true},
                                           Case{"corridor", false}, Case{"corridor", true}),
                         [](const auto& test) {
                           return test.param.world + (test.param.lms ? "_lms200" : "_urg04lx");
                         });

}  // namespace
}  // namespace splam::sim
