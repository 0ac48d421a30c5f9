// Worst-case step and memory over a long run with a long-range laser.
//
// BM_LongRangeRun/<method>: the `long_corridors` world (bench/worlds/long_corridors.yaml, a
// 60 m x 40 m ring of 2.5 m corridors) with a 181-beam SICK at 1 deg and an 80 m range, its route
// (once round and 28 m on) driven twice, simulated once: the second lap sees nothing new. Each
// iteration runs one SLAM method over the whole log through runtime::SlamDriver, as `splam slam`
// does. The time is the whole run's; the counters give what a user worries about on a long log:
// - median_step_ms, max_step_ms: the median and the slowest step (predict + update) of the run;
// - heap_peak_mb: the largest heap in use over the run (glibc's mallinfo2, sampled every 100
//   steps, minus the heap in use before the method was made): live allocations, unlike the
//   resident size, which keeps what earlier runs freed;
// - heap_q1_mb .. heap_q4_mb: the heap in use at the end of each quarter of the log. Memory
//   bounded by the map levels off once the map is complete (the second lap, from the middle of
//   the log, adds no walls).
// - map_q1 .. map_q4: the method's MapSize() then (control points, landmarks or keyframes).
// ekf-bspline takes about 100 s a run; pass --benchmark_filter to leave it out.
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "estimation/slam_method.h"
#include "io/world_file.h"
#include "runtime/slam_driver.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

#ifndef SPLAM_BENCH_WORLDS
#error "SPLAM_BENCH_WORLDS must name the bench/worlds directory"
#endif

namespace {

using splam::kernel::Pose2;

constexpr std::array<const char*, 5> kMethods = {"ekf-lines", "topological", "topological-graph",
                                                 "graph", "ekf-bspline"};

// The heap in use (allocated and not freed, mmapped blocks included), MB.
double HeapMb() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

struct LongRangeLog {
  Pose2 start;
  std::vector<splam::sim::SensorFrame> frames;
};

const LongRangeLog& Log() {
  static const LongRangeLog log = [] {
    const splam::sim::World world =
        *splam::io::LoadValidWorld(std::string(SPLAM_BENCH_WORLDS) + "/long_corridors.yaml").value;
    const splam::sim::RayCaster caster(world);
    splam::sim::SimulatorOptions options;
    options.laser = splam::sim::LaserOptions::Lms200(1.0);
    options.laser.max_range_m = 80.0;
    splam::sim::Simulator simulator(caster, options, *world.start, 1);
    std::vector<Eigen::Vector2d> route = world.route;
    route.insert(route.end(), world.route.begin(), world.route.end());
    return LongRangeLog{*world.start, splam::sim::FollowRoute(&simulator, route, {}).frames};
  }();
  return log;
}

void BM_LongRangeRun(benchmark::State& state) {
  const char* method = kMethods[static_cast<std::size_t>(state.range(0))];
  const LongRangeLog& log = Log();
  const std::size_t n = log.frames.size();
  std::vector<double> steps, quarters, quarter_maps;
  double growth = 0.0;
  for (auto _ : state) {
    const double before = HeapMb();
    splam::runtime::SlamDriver driver(std::move(
        *splam::estimation::SlamRegistry::Global().Make(method, nullptr, {log.start, {}}).value));
    quarters.clear();
    quarter_maps.clear();
    for (std::size_t i = 0; i < n; ++i) {
      driver.Step(log.frames[i].odometry_pose, &log.frames[i].scan, Pose2());
      if (i % 100 == 0 || i + 1 == n) growth = std::max(growth, HeapMb() - before);
      if ((i + 1) * 4 / n != i * 4 / n) {
        quarters.push_back(HeapMb() - before);
        quarter_maps.push_back(static_cast<double>(driver.method().MapSize()));
      }
    }
    steps = driver.update_ms();
  }
  std::sort(steps.begin(), steps.end());
  state.SetLabel(method);
  state.counters["median_step_ms"] = steps[steps.size() / 2];
  state.counters["max_step_ms"] = steps.back();
  state.counters["heap_peak_mb"] = growth;
  for (std::size_t q = 0; q < quarters.size(); ++q) {
    const std::string quarter = "q" + std::to_string(q + 1);
    state.counters["heap_" + quarter + "_mb"] = quarters[q];
    state.counters["map_" + quarter] = quarter_maps[q];
  }
}
BENCHMARK(BM_LongRangeRun)
    ->DenseRange(0, static_cast<int>(kMethods.size()) - 1)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
