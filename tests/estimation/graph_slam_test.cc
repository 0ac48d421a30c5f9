// Graph SLAM: registration, correlative search, pose graph, loop closure and whole runs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "estimation/correlative_matcher.h"
#include "estimation/distance_grid.h"
#include "estimation/graph_slam.h"
#include "estimation/pose_graph.h"
#include "estimation/scan_registration.h"
#include "kernel/angle.h"
#include "sim/builtin_worlds.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::estimation {
namespace {

using kernel::Pose2;

// A free pose of `world` drawn uniformly (fixed generator).
Pose2 FreePose(const sim::Simulator& simulator, std::mt19937* gen) {
  std::uniform_real_distribution<double> x(-1.0, 1.0);
  for (;;) {
    const Pose2 p(8.0 + 7.0 * x(*gen), 8.0 + 7.0 * x(*gen), M_PI * x(*gen));
    if (simulator.IsFree(p)) return p;
  }
}

class ComplexWorld : public ::testing::Test {
 protected:
  ComplexWorld()
      : world_(*sim::BuiltinWorld("complex")),
        caster_(world_),
        simulator_(caster_, {}, *world_.start, 1) {}
  // The laser's points in the robot frame at `pose` (the simulated URG-04LX, with noise).
  std::vector<Eigen::Vector2d> Points(const Pose2& pose) {
    sim::LaserOptions laser = simulator_.options().laser;
    const kernel::Scan scan =
        sim::SimulateLaser(caster_, laser, pose * laser.robot_T_laser, 0.0, &random_);
    return laser.robot_T_laser * scan.HitPoints();
  }
  // The same in the world frame, with the normals of their free side.
  std::vector<OrientedPoint> WorldPoints(const Pose2& pose) {
    std::vector<OrientedPoint> points =
        OrientTowards(Points(pose), simulator_.options().laser.robot_T_laser.translation(), 0.3);
    for (auto& p : points) p = {pose * p.point, pose.Rotation() * p.normal};
    return points;
  }
  sim::World world_;
  sim::RayCaster caster_;
  sim::Simulator simulator_;
  kernel::Random random_{7};
};

// Property: a scan registered against the distance field of a scan taken nearby (placed at its
// true pose) recovers its true pose from a prior up to 0.15 m and 0.1 rad off.
TEST_F(ComplexWorld, RegistrationRecoversKnownTransforms) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int trials = 0, recovered = 0;
  double worst_m = 0.0, worst_rad = 0.0;
  while (trials < 100) {
    const Pose2 a = FreePose(simulator_, &gen);
    const Pose2 b = a * Pose2(0.2 * u(gen), 0.2 * u(gen), 0.1 * u(gen));
    if (!simulator_.IsFree(b)) continue;
    const std::vector<OrientedPoint> map_points = WorldPoints(a);
    const std::vector<Eigen::Vector2d> scan = Points(b);
    if (map_points.size() < 100 || scan.size() < 100) continue;
    ++trials;
    const DistanceGrid grid = DistanceGrid::Build(map_points, 0.1, 0.5, 0.5);
    const Pose2 prior = b * Pose2(0.15 * u(gen), 0.15 * u(gen), 0.1 * u(gen));
    const RegistrationResult r = RegisterPoints(scan, grid, prior, RegistrationOptions{});
    const Pose2 error = b.Between(r.pose);
    worst_m = std::max(worst_m, error.translation().norm());
    worst_rad = std::max(worst_rad, std::abs(error.theta()));
    recovered += error.translation().norm() < 0.03 && std::abs(error.theta()) < 0.01;
  }
  EXPECT_GE(recovered, 95) << "worst " << worst_m << " m, " << worst_rad << " rad";
}

}  // namespace
}  // namespace splam::estimation
