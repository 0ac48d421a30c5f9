// Cost over a long run: does a method slow down, or its memory grow, as the
// log gets longer in a world it has already mapped?
//
// BM_LongRun/<method>/<hours>: `office-long` (a 30 m x 12 m floor of eleven rooms off a corridor)
// with the simulator's default URG-04LX at 10 Hz, its route driven lap after lap (about 3 minutes
// a lap) for <hours> of simulated time, simulated lap by lap as the SLAM goes, so that the log
// is never held whole. Every lap after the first revisits the same corridor: a method whose cost
// follows the map stays flat, one whose cost follows the log grows. Counters, for each hour hN
// of the log:
// - median_hN_ms, p99_hN_ms: the median and the 99th percentile of its steps (predict + update);
// - heap_hN_mb: the heap in use at its end (glibc's mallinfo2, minus the heap before the method
//   was made, the benchmark's own records reserved before), as in long_range_benchmark;
// - map_hN: the method's MapSize() then;
// and rmse_m, the position RMSE of the whole trajectory after Finish.
// Run one at a time, alone: two hours of the graph SLAM take about 1.5 minutes with its defaults
// and 6 optimising the whole graph at every flush (docs/benchmarks.md). E.g.
//   build/bench/long_run_benchmark --benchmark_filter='BM_LongRun/graph/2/'
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/pose_graph/graph_slam.h"
#include "estimation/slam_method.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace {

using splam::kernel::Pose2;

// The heap in use (allocated and not freed, mmapped blocks included), MB.
double HeapMb() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return values[k];
}

using splam::estimation::GraphSlamOptions;

// `tweak`, when given, changes the graph SLAM's default options.
void BM_LongRun(benchmark::State& state, const char* method,
                void (*tweak)(GraphSlamOptions&) = nullptr) {
  const int hours = static_cast<int>(state.range(0));
  const splam::sim::World world = *splam::sim::BuiltinWorld("office-long");
  const splam::sim::RayCaster caster(world);
  std::vector<std::vector<double>> steps(static_cast<std::size_t>(hours));
  std::vector<double> heap(static_cast<std::size_t>(hours)), map(heap.size());
  double rmse = 0.0;
  for (auto _ : state) {
    splam::sim::Simulator simulator(caster, {}, *world.start, 1);
    const Pose2& robot_T_laser = simulator.options().laser.robot_T_laser;
    // The benchmark's own records are allocated before the heap is read, so that the heap
    // counted is the method's (and a lap of the simulator's frames).
    std::vector<Eigen::Vector2d> truth;
    truth.reserve(static_cast<std::size_t>(3600 * 12 * hours));
    for (std::vector<double>& hour : steps) hour.reserve(3600 * 12);
    const auto& registry = splam::estimation::SlamRegistry::Global();
    const std::unique_ptr<splam::estimation::SlamOptions> options =
        registry.Find(method)->default_options({});
    if (tweak != nullptr)
      tweak(static_cast<splam::estimation::SlamOptionsOf<GraphSlamOptions>&>(*options).options());
    const double before = HeapMb();
    const std::unique_ptr<splam::estimation::SlamMethod> slam =
        std::move(*registry.Make(method, options.get(), {*world.start, {}}).value);
    std::optional<Pose2> last_odometry;
    bool first_lap = true;
    while (simulator.time_s() < 3600.0 * hours) {
      splam::sim::RouteRun lap = splam::sim::FollowRoute(&simulator, world.route, {});
      if (!lap.completed) state.SkipWithError(lap.message.c_str());
      // A lap's first frame is sensed where the previous lap's last one was.
      for (std::size_t i = first_lap ? 0 : 1; i < lap.frames.size(); ++i) {
        const splam::sim::SensorFrame& frame = lap.frames[i];
        const auto hour = static_cast<std::size_t>(frame.time_s / 3600.0);
        if (hour >= steps.size()) break;
        const auto begin = std::chrono::steady_clock::now();
        if (last_odometry) slam->Predict(last_odometry->Between(frame.odometry_pose));
        last_odometry = frame.odometry_pose;
        slam->Update(frame.scan, robot_T_laser);
        steps[hour].push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
                .count());
        heap[hour] = HeapMb() - before;
        map[hour] = static_cast<double>(slam->MapSize());
        truth.push_back(frame.true_pose.translation());
      }
      first_lap = false;
      if (!lap.completed) break;
    }
    slam->Finish();
    for (const auto& [name, value] : slam->Statistics().map)
      state.counters[name] = static_cast<double>(value);
    const std::vector<Pose2> estimate = slam->Trajectory();
    for (std::size_t i = 0; i < estimate.size() && i < truth.size(); ++i)
      rmse += (estimate[i].translation() - truth[i]).squaredNorm();
    rmse = std::sqrt(rmse / static_cast<double>(std::max<std::size_t>(1, truth.size())));
  }
  for (std::size_t h = 0; h < steps.size(); ++h) {
    const std::string hour = "h" + std::to_string(h + 1);
    state.counters["median_" + hour + "_ms"] = Quantile(steps[h], 0.5);
    state.counters["p99_" + hour + "_ms"] = Quantile(steps[h], 0.99);
    state.counters["heap_" + hour + "_mb"] = heap[h];
    state.counters["map_" + hour] = map[h];
  }
  state.counters["rmse_m"] = rmse;
  state.SetLabel(method);
}
BENCHMARK_CAPTURE(BM_LongRun, graph, "graph")
    ->Arg(2)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
// The graph SLAM optimising the whole graph at every flush of closures (the defaults before
// session 35's deferred_optimization_fraction).
BENCHMARK_CAPTURE(
    BM_LongRun, graph_every_flush, "graph",
    +[](GraphSlamOptions& o) { o.back_end.advanced.deferred_optimization_fraction = 0.0; })
    ->Arg(2)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
// Every keyframe a node of the graph, trimmed or not (the defaults before session 36's
// merge_trimmed_keyframes).
BENCHMARK_CAPTURE(
    BM_LongRun, graph_without_merging, "graph",
    +[](GraphSlamOptions& o) { o.back_end.merge_trimmed_keyframes = false; })
    ->Arg(2)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
// Closures that agree with the graph waiting for its whole optimisation without optimising its
// last keyframes meanwhile.
BENCHMARK_CAPTURE(
    BM_LongRun, graph_without_local, "graph",
    +[](GraphSlamOptions& o) { o.back_end.advanced.local_optimization_keyframes = 0; })
    ->Arg(2)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_LongRun, topological, "topological")
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
