#include "estimation/occupancy_grid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/random.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

// Every cell a segment crosses, in order, each a side neighbour of the one before, from the
// start's cell to the end's: no gap a wall could hide in, no cell counted twice.
TEST(OccupancyGrid, CellsOnASegmentAreTheOnesItCrosses) {
  const OccupancyGrid grid({-3.0, -2.0}, 0.05, 200, 200);
  kernel::Random random(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector2d a(random.Uniform(-3, 7), random.Uniform(-2, 8));
    const Eigen::Vector2d b = trial % 10 == 0
                                  ? Eigen::Vector2d(a.x(), random.Uniform(-2, 8))  // vertical
                                  : Eigen::Vector2d(random.Uniform(-3, 7), random.Uniform(-2, 8));
    const std::vector<Eigen::Vector2i> cells = CellsOnSegment(grid, a, b);
    ASSERT_EQ(cells.front(), *grid.CellOf(a));
    ASSERT_EQ(cells.back(), *grid.CellOf(b));
    const Eigen::Vector2i span = *grid.CellOf(b) - *grid.CellOf(a);
    ASSERT_EQ(cells.size(), static_cast<std::size_t>(std::abs(span.x()) + std::abs(span.y()) + 1));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i > 0) {
        ASSERT_EQ((cells[i] - cells[i - 1]).cwiseAbs().sum(), 1) << "trial " << trial;
      }
      // The segment passes within half a diagonal of the cell's centre.
      const Eigen::Vector2d c = grid.CenterOf(cells[i].x(), cells[i].y());
      const Eigen::Vector2d d = b - a;
      const double t =
          d.squaredNorm() > 0 ? std::clamp((c - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      EXPECT_LE((a + t * d - c).norm(), 0.05 * std::sqrt(0.5) + 1e-9) << "trial " << trial;
    }
  }
}

// A simulated robot's scans at its true poses in `complex` (range noise: sigma as a fraction of
// the range), and the grid they make.
struct TrueRouteGrid {
  sim::World world = *sim::BuiltinWorld("complex");
  sim::RayCaster caster{world};
  sim::SimulatorOptions simulator_options;
  sim::RouteRun run;
  OccupancyGridOptions options;
  kernel::Result<OccupancyGrid> grid = kernel::Result<OccupancyGrid>::Fail("not built");

  explicit TrueRouteGrid(double noise_fraction) {
    simulator_options.laser.noise_fraction = noise_fraction;
    sim::Simulator simulator(caster, simulator_options, *world.start, 3);
    run = sim::FollowRoute(&simulator, world.route, {});
    std::vector<evaluation::PlacedScan> placed;
    for (const sim::SensorFrame& f : run.frames)
      placed.push_back({f.true_pose, simulator_options.laser.robot_T_laser, &f.scan});
    grid = BuildOccupancyGrid(placed, options);
  }
};

// Cells against the true world: occupied ones within `wall_m` of a wall, free ones off the walls
// and outside obstacles, the true points the beams hit in (or next to) an occupied cell.
void ExpectMatchesTheWorld(const TrueRouteGrid& t, double wall_m) {
  ASSERT_TRUE(t.run.completed);
  ASSERT_TRUE(t.grid.ok()) << t.grid.error;
  const OccupancyGrid& grid = *t.grid;
  const OccupancyGridOptions& options = t.options;
  EXPECT_DOUBLE_EQ(grid.resolution_m(), 0.05);
  const auto state = [&](int x, int y) {
    return grid.State(x, y, options.occupied_threshold, options.free_threshold);
  };
  int occupied = 0, occupied_on_wall = 0, free = 0, free_off_wall = 0;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d c = grid.CenterOf(x, y);
      const double wall = t.caster.Nearest(c, 1.0).range_m;  // distance to the nearest obstacle
      if (state(x, y) == CellState::kOccupied) {
        ++occupied;
        occupied_on_wall += wall <= wall_m;
      } else if (state(x, y) == CellState::kFree) {
        ++free;
        free_off_wall += wall > 0.025 && !t.caster.IsInsideObstacle(c);
      }
    }
  }
  ASSERT_GT(occupied, 1000);
  ASSERT_GT(free, 50000);
  EXPECT_GE(occupied_on_wall, 0.98 * occupied) << occupied_on_wall << " of " << occupied;
  EXPECT_GE(free_off_wall, 0.995 * free) << free_off_wall << " of " << free;
  int hits = 0, found = 0;
  for (std::size_t i = 0; i < t.run.frames.size(); i += 10) {
    const sim::SensorFrame& f = t.run.frames[i];
    const Pose2 laser = f.true_pose * t.simulator_options.laser.robot_T_laser;
    for (std::size_t b = 0; b < f.scan.size(); b += 5) {
      if (f.beam_obstacles[b] < 0 || !f.scan.IsHit(b)) continue;
      const double heading = laser.theta() + f.scan.BeamAngle(b);
      const Eigen::Vector2d direction(std::cos(heading), std::sin(heading));
      const sim::RayHit truth = t.caster.Cast({laser.translation(), direction}, 100.0);
      const Eigen::Vector2i c = *grid.CellOf(laser.translation() + truth.range_m * direction);
      ++hits;
      bool near = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          near = near || state(c.x() + dx, c.y() + dy) == CellState::kOccupied;
      found += near;
    }
  }
  ASSERT_GT(hits, 1000);
  EXPECT_GE(found, 0.97 * hits) << found << " of " << hits;
}

// Exact ranges: every occupied cell has a wall through it or its side neighbour (half a cell's
// diagonal plus a cell).
TEST(OccupancyGrid, MatchesTheTrueWorld) { ExpectMatchesTheWorld(TrueRouteGrid(0.0), 0.075); }

// The simulated URG's range noise (1 % of up to 4 m: sigma up to 4 cm) spreads the walls over
// three sigma.
TEST(OccupancyGrid, MatchesTheTrueWorldThroughRangeNoise) {
  ExpectMatchesTheWorld(TrueRouteGrid(0.01), 0.15);
}

TEST(OccupancyGrid, CellsNeverObservedAreUnknownAndOneScanCountsOnce) {
  // Three beams 2 m to a return, from a laser at the origin, over the same cells near it.
  kernel::Scan scan;
  scan.start_angle_rad = 0.05;
  scan.angular_step_rad = 0.01;
  scan.max_range_m = 5.0;
  scan.ranges_m = {2.0, 2.0, 2.0};
  OccupancyGridOptions options;
  const kernel::Result<OccupancyGrid> grid =
      BuildOccupancyGrid({{Pose2(), Pose2(), &scan}}, options);
  ASSERT_TRUE(grid.ok()) << grid.error;
  const Eigen::Vector2i near = *grid->CellOf({0.52, 0.03});
  // Crossed by all three beams, one miss: p = miss_probability.
  EXPECT_NEAR(grid->Probability(near.x(), near.y()), options.miss_probability, 1e-6);
  const Eigen::Vector2i end = *grid->CellOf({2.0 * std::cos(0.05), 2.0 * std::sin(0.05)});
  EXPECT_NEAR(grid->Probability(end.x(), end.y()), options.hit_probability, 1e-6);
  const Eigen::Vector2i side = *grid->CellOf({1.0, -0.06});
  EXPECT_FALSE(grid->observed(side.x(), side.y()));
  EXPECT_EQ(grid->State(side.x(), side.y(), 0.65, 0.196), CellState::kUnknown);
  // Ten times the same scan: clamped at the bounds.
  const std::vector<evaluation::PlacedScan> ten(10, {Pose2(), Pose2(), &scan});
  const kernel::Result<OccupancyGrid> again = BuildOccupancyGrid(ten, options);
  EXPECT_NEAR(again->Probability(near.x(), near.y()), options.min_probability, 1e-6);
  EXPECT_NEAR(again->Probability(end.x(), end.y()), options.max_probability, 1e-6);
}

TEST(OccupancyGrid, RefusesBadOptionsAndGridsTooLarge) {
  kernel::Scan scan;
  scan.angular_step_rad = 0.01;
  scan.max_range_m = 5.0;
  scan.ranges_m = {2.0};
  const std::vector<evaluation::PlacedScan> far = {{Pose2(), Pose2(), &scan},
                                                   {Pose2(9e5, 9e5, 0), Pose2(), &scan}};
  const kernel::Result<OccupancyGrid> huge = BuildOccupancyGrid(far);
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.error.find("max_cells"), std::string::npos) << huge.error;
  OccupancyGridOptions bad;
  bad.hit_probability = 0.4;
  EXPECT_FALSE(bad.Validate().ok());
  bad = {};
  bad.free_threshold = 0.7;
  EXPECT_FALSE(bad.Validate().ok());
  bad = {};
  bad.resolution_m = 0;
  EXPECT_FALSE(BuildOccupancyGrid(far, bad).ok());
  EXPECT_FALSE(BuildOccupancyGrid({}).ok());  // nothing to map
  const kernel::Result<OccupancyGrid> diverged =
      BuildOccupancyGrid({{Pose2(1e300, 0, 0), Pose2(), &scan}});
  ASSERT_FALSE(diverged.ok());
  EXPECT_NE(diverged.error.find("beyond +-1e+06 m"), std::string::npos) << diverged.error;
}

}  // namespace
}  // namespace splam::estimation
