// EKF-SLAM cost against map size.
// - BM_EkfLinesScan: one prediction and the update with 5 re-observed lines, in a map
//   of N line landmarks (state size 3 + 2N).
// - BM_EkfCorrection: one correction with 30 beams against one spline of 20 control
//   points in a state of N control points: the step that dominates the B-spline EKF, O(N^2).
// - BM_EkfBSplineComplexScan: a whole B-spline EKF step (prediction, curve extraction,
//   association, corrections) on URG-04LX scans of the `complex` route, with the map built so far.
// - BM_TopologicalComplexScan: a whole topological B-spline SLAM step on the same
//   scans, in a map of max(N, M) curves: the M curves of `complex` mapped on a first pass of the
//   route, completed to N by copies of them in far rooms. Association looks only at the local
//   region, so the time must not grow with N.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "estimation/ekf/ekf_core.h"
#include "estimation/ekf/ekf_line_slam.h"
#include "estimation/slam_method.h"
#include "estimation/topological/topological_slam.h"
#include "kernel/angle.h"
#include "kernel/random.h"
#include "runtime/log_replay.h"
#include "sim/builtin_worlds.h"
#include "sim/simulator.h"

namespace {

using splam::kernel::Pose2;

// N walls around the origin at distinct (rho, theta), seen from the origin.
splam::kernel::LineExtraction Walls(int first, int count) {
  splam::kernel::LineExtraction out;
  for (int i = first; i < first + count; ++i) {
    splam::kernel::LineFeature f;
    f.theta_rad = splam::kernel::WrapAngle(0.61803 * i * 2 * splam::kernel::kPi);
    f.rho_m = 2.0 + 0.37 * (i % 23);
    const Eigen::Vector2d n(std::cos(f.theta_rad), std::sin(f.theta_rad)), t(-n.y(), n.x());
    f.start = f.rho_m * n - t;
    f.end = f.rho_m * n + t;
    f.covariance = Eigen::Vector2d(1e-4, 1e-5).asDiagonal();
    f.point_indices.resize(50);
    out.lines.push_back(f);
  }
  return out;
}

void BM_EkfLinesScan(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  splam::estimation::EkfLineSlamOptions options;
  options.gate_probability = 0.99;
  options.min_observations_to_add = 1;  // build the map from single sightings
  splam::estimation::EkfLineSlam slam(Pose2(), Eigen::Matrix3d::Identity() * 1e-6, options);
  for (int i = 0; i < n; i += 10) slam.Update(Walls(i, std::min(10, n - i)), Pose2());
  const splam::kernel::LineExtraction seen = Walls(0, 5);
  for (auto _ : state) {
    slam.Predict(Pose2(1e-4, 0.0, 0.0));
    benchmark::DoNotOptimize(slam.Update(seen, Pose2()).associated);
  }
  state.counters["landmarks"] = static_cast<double>(slam.num_lines());
}
BENCHMARK(BM_EkfLinesScan)
    ->Arg(10)
    ->Arg(50)
    ->Arg(100)
    ->Arg(200)
    ->Arg(500)
    ->Unit(benchmark::kMicrosecond);

void BM_EkfCorrection(benchmark::State& state) {
  const Eigen::Index n = 3 + 2 * state.range(0);
  splam::kernel::Random random(3);
  splam::estimation::EkfCore ekf(Pose2(), Eigen::Matrix3d::Identity() * 1e-2);
  // Landmarks correlated with the pose, as after a run.
  Eigen::MatrixXd g_r(n - 3, 3);
  for (Eigen::Index i = 0; i < g_r.size(); ++i) g_r.data()[i] = random.Uniform(-1, 1);
  ekf.Append(Eigen::VectorXd::Zero(n - 3), g_r, Eigen::MatrixXd::Identity(n - 3, n - 3) * 1e-2);
  Eigen::MatrixXd h_r(30, 3), h_b(30, 40);
  for (Eigen::Index i = 0; i < h_r.size(); ++i) h_r.data()[i] = random.Uniform(-1, 1);
  for (Eigen::Index i = 0; i < h_b.size(); ++i) h_b.data()[i] = random.Uniform(-0.1, 0.1);
  const Eigen::VectorXd nu = Eigen::VectorXd::Zero(30);
  const Eigen::MatrixXd r = Eigen::MatrixXd::Identity(30, 30) * 1e-2;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        ekf.Correct(h_r, {splam::estimation::JacobianBlock{n - 40, h_b}}, nu, r));
  }
  state.counters["control_points"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_EkfCorrection)
    ->Arg(100)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Unit(benchmark::kMicrosecond);

// The `complex` world's route driven with a URG-04LX (seed 1): its start pose and sensor frames.
struct ComplexRoute {
  splam::kernel::Pose2 start;
  std::vector<splam::sim::SensorFrame> frames;
};
ComplexRoute DriveComplexRoute() {
  const splam::sim::World world = *splam::sim::BuiltinWorld("complex");
  const splam::sim::RayCaster caster(world);
  splam::sim::SimulatorOptions sim_options;
  sim_options.laser = splam::sim::LaserOptions::Urg04lx();
  splam::sim::Simulator simulator(caster, sim_options, *world.start, 1);
  return {*world.start, splam::sim::FollowRoute(&simulator, world.route, {}).frames};
}

// Each iteration is one step of the SLAM driver (predict + update), as `splam slam` runs it.
void BM_EkfBSplineComplexScan(benchmark::State& state) {
  const auto [start, frames] = DriveComplexRoute();
  splam::estimation::SlamOptionsOf<splam::estimation::EkfBSplineSlamOptions> options;
  options.options().association = state.range(0) == 0 ? "pedraza" : "curvature";
  std::size_t i = 0, control_points = 0;
  std::optional<splam::runtime::SlamDriver> driver;
  for (auto _ : state) {
    if (i % frames.size() == 0) {  // start the route again
      state.PauseTiming();
      driver.emplace(std::move(*splam::estimation::SlamRegistry::Global()
                                    .Make("ekf-bspline", &options, {start, {}})
                                    .value));
      i = 0;
      state.ResumeTiming();
    }
    driver->Step(frames[i].odometry_pose, &frames[i].scan, Pose2());
    control_points = std::max(control_points, driver->method().MapSize());
    ++i;
  }
  state.SetLabel(options.options().association);
  state.counters["max_control_points"] = static_cast<double>(control_points);
}
BENCHMARK(BM_EkfBSplineComplexScan)
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1484)
    ->Unit(benchmark::kMillisecond);

void BM_TopologicalComplexScan(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const auto [start, frames] = DriveComplexRoute();
  // First pass: the map of the world.
  std::vector<splam::kernel::SplineCurve> room;
  {
    splam::runtime::SlamDriver driver(std::move(*splam::estimation::SlamRegistry::Global()
                                                     .Make("topological", nullptr, {start, {}})
                                                     .value));
    splam::runtime::ReplayFrames(frames, Pose2(), &driver);
    for (const splam::estimation::MapSpline& s : driver.method().Map().splines)
      room.push_back(splam::kernel::DescribeCurve(s.spline));
  }
  std::vector<splam::kernel::SplineCurve> prior = room;
  // The timed loop drives the class itself: a prior map is added with AddMapCurve, which the
  // SlamMethod interface does not offer.
  for (int copy = 1; prior.size() < n; ++copy) {  // rooms 40 m apart along x and y
    const Eigen::Vector2d offset(40.0 * (copy % 8), 40.0 * (copy / 8));
    for (std::size_t k = 0; k < room.size() && prior.size() < n; ++k) {
      std::vector<Eigen::Vector2d> points = room[k].spline.control_points();
      for (Eigen::Vector2d& p : points) p += offset;
      prior.push_back(splam::kernel::DescribeCurve(
          *splam::kernel::CubicBSpline::Create(std::move(points), room[k].spline.knots())));
    }
  }
  std::size_t i = 0, curves = 0;
  std::unique_ptr<splam::estimation::TopologicalSlam> slam;
  for (auto _ : state) {
    if (i % frames.size() == 0) {  // start the route again in the prior map
      state.PauseTiming();
      slam = std::make_unique<splam::estimation::TopologicalSlam>(start);
      for (const auto& curve : prior) slam->AddMapCurve(curve);
      i = 0;
      state.ResumeTiming();
    }
    if (i > 0) slam->Predict(frames[i - 1].odometry_pose.Between(frames[i].odometry_pose));
    benchmark::DoNotOptimize(slam->Update(frames[i].scan).local_map_curves);
    curves = std::max(curves, slam->num_curves());
    ++i;
  }
  state.counters["map_curves"] = static_cast<double>(curves);
}
BENCHMARK(BM_TopologicalComplexScan)
    ->Arg(10)
    ->Arg(100)
    ->Arg(500)
    ->Iterations(1484)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
