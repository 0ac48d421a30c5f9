// EKF-SLAM cost per scan against the number of landmarks (issue 4): one prediction and the
// update with 5 re-observed lines, in a map of N line landmarks (state size 3 + 2N).
#include <benchmark/benchmark.h>

#include <cmath>

#include "estimation/ekf_line_slam.h"
#include "kernel/angle.h"

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

}  // namespace

BENCHMARK_MAIN();
